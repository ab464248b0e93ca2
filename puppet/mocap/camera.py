"""A webcam or a video file read in-process: MediaPipe's pose landmarker on a thread,
its landmarks handed on as the MediaPipe-to-OSC bridge's messages (``puppet[webcam]``).

    puppet play biped-mocap --mocap webcam:0          # the first camera
    puppet play biped-mocap --mocap video:take.mp4    # a film, played at its frame rate

Two threads. The grabber reads pictures with OpenCV (a camera at its own pace, a video
at its frame rate by the wall clock) into a slot of one: a picture the landmarker has
not taken yet is replaced by the newer one (counted, ``skipped_pictures``), so the
landmarker always works on the newest and never falls behind the performer. The
landmarker thread runs MediaPipe's pose landmarker (``PoseLandmarker``: the legacy
``solutions.pose`` graph at model complexity 1, whose model ships inside MediaPipe
0.10.21's wheel) on it and hands the 33 landmarks to ``OscSource.receive`` as the
bridge would send them (``mediapipe_bridge.encode_pose``, unmirrored: OpenCV's picture
is the camera's, not a selfie view), so the decoder, the guard, the mapping
(``mediapipe-image``), the 1-euro filter, the queue, the status and the recording are
those of ``--mocap udp://... --mocap-format mediapipe-osc``. A picture with no pose is
the bridge's "no pose" (counted; no sample: tracking is lost after 0.25 s, and the
interface's keys take the figure). The picture's x is rescaled about its middle to a
4:3 picture's widths (the mapping's convention), whatever the camera's aspect.

A take is recorded as any live take is (the channels, at the step they acted), so its
log replays bit-identically with neither OpenCV nor MediaPipe installed. Without them
``start`` says, in one line, ``pip install 'puppet[webcam]'``; a camera that does not
open or a video that cannot be read is a one-line error too.
"""

from __future__ import annotations

import contextlib
import os
import threading
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from puppet.data.errors import UsageError
from puppet.mocap.mediapipe import LANDMARKS
from puppet.mocap.mediapipe_bridge import MediaPipeBridgeDecoder, encode_pose
from puppet.mocap.source import LOST_AFTER, OscSource

INSTALL = "pip install 'puppet[webcam]'"
MEDIAPIPE = "0.10.21"  # the version pyproject's webcam extra pins (its wheel holds the model)
MODEL = "modules/pose_landmark/pose_landmark_full.tflite"  # inside the mediapipe package
ASPECT = 4.0 / 3.0  # the picture the mapping's x scale assumes (mediapipe-image)
DEFAULT_FPS = 30.0  # a video that does not say its frame rate
CAMERA_GIVES_UP = 2.0  # s of failed reads before a camera is taken as gone


def parse_camera(value: str, option: str = "--mocap") -> tuple[str, int | str]:
    """``webcam:N`` -> ("webcam", N); ``webcam:`` is camera 0; ``video:PATH`` ->
    ("video", PATH)."""
    kind, _, rest = value.partition(":")
    if kind == "webcam":
        rest = rest or "0"
        if not rest.isdigit():
            raise UsageError(f"{option} {value}: expected webcam:N, N a camera's number "
                             f"(webcam:0 is the first camera)")
        return kind, int(rest)
    if kind == "video" and rest:
        return kind, rest
    raise UsageError(f"{option} {value}: expected webcam:N (a camera's number) or "
                     f"video:PATH (a film)")


@contextlib.contextmanager
def _quiet_stderr():
    """OpenCV and MediaPipe's C++ write their logs straight to file descriptor 2 (a
    camera that is not there, TensorFlow Lite's delegate): silenced while they start."""
    try:
        saved = os.dup(2)
    except OSError:
        yield
        return
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 2)
            yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)


def _cv2(what: str):
    try:
        os.environ.setdefault("OPENCV_LOG_LEVEL", "OFF")
        import cv2
    except Exception as exc:  # noqa: BLE001 - not installed, or built against another numpy
        raise UsageError(f"{what} needs OpenCV and MediaPipe, an optional extra: {INSTALL} "
                         f"({type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''})"
                         ) from None
    return cv2


class OpenCvCapture:
    """A camera or a video file through OpenCV, read as RGB pictures. Opening reads the
    first picture, so a camera that gives none, or a file that is no video, fails here."""

    def __init__(self, kind: str, where: int | str, name: str):
        self.is_video = kind == "video"
        if self.is_video and not Path(where).is_file():
            raise UsageError(f"--mocap {name}: no such file")
        cv2 = self.cv2 = _cv2(f"--mocap {name}")
        with _quiet_stderr():
            cap = cv2.VideoCapture(where if kind == "webcam" else str(where))
            ok, picture = cap.read() if cap.isOpened() else (False, None)
        if not ok or picture is None:
            cap.release()
            raise UsageError(f"--mocap {name}: " + (
                "OpenCV cannot read a picture from this file (not a video it can decode)"
                if self.is_video else f"no camera {where} (OpenCV could not open it or "
                                      f"read a picture from it)"))
        self.cap = cap
        fps = float(cap.get(cv2.CAP_PROP_FPS) or 0.0)
        self.fps = fps if 1.0 <= fps <= 1000.0 else DEFAULT_FPS
        self.size = (int(picture.shape[1]), int(picture.shape[0]))
        self._first = picture

    def read(self):
        """The next picture (height x width x 3, RGB), or None (the video's end, or a
        camera that failed this time)."""
        if self._first is not None:
            picture, self._first = self._first, None
        else:
            ok, picture = self.cap.read()
            if not ok or picture is None:
                return None
        return self.cv2.cvtColor(picture, self.cv2.COLOR_BGR2RGB)

    def release(self) -> None:
        self.cap.release()


class PoseLandmarker:
    """MediaPipe's pose landmarker on one stream of pictures: ``landmarker(rgb)`` ->
    the 33 landmarks as (x, y, z, visibility) in picture widths and heights, or None
    (no pose). Tracking mode (each picture starts from the last one's pose); MediaPipe's
    own smoothing is off, the stream's 1-euro filter does it (its lag as documented)."""

    def __init__(self, name: str = "webcam"):
        _cv2(f"--mocap {name}")  # MediaPipe's wheel brings OpenCV: say the extra once
        try:
            import mediapipe
            from mediapipe.python.solutions import pose
        except Exception as exc:  # noqa: BLE001 - absent, or the wrong numpy/protobuf
            raise UsageError(f"--mocap {name} needs MediaPipe {MEDIAPIPE}, an optional "
                             f"extra: {INSTALL} ({type(exc).__name__}: "
                             f"{str(exc).splitlines()[0] if str(exc) else ''})") from None
        if not (Path(mediapipe.__file__).parent / MODEL).is_file():
            raise UsageError(f"--mocap {name}: MediaPipe {getattr(mediapipe, '__version__', '?')}"
                             f" has no pose model in its wheel (it would download one); "
                             f"{INSTALL} installs {MEDIAPIPE}, which has")
        with _quiet_stderr():
            self.pose = pose.Pose(static_image_mode=False, model_complexity=1,
                                  smooth_landmarks=False, enable_segmentation=False,
                                  min_detection_confidence=0.5, min_tracking_confidence=0.5)
            self.pose.process(np.zeros((64, 64, 3), np.uint8))  # its start-up logs, here

    def __call__(self, rgb) -> list[tuple[float, float, float, float]] | None:
        result = self.pose.process(rgb)
        if result.pose_landmarks is None:
            return None
        return [(m.x, m.y, m.z, m.visibility) for m in result.pose_landmarks.landmark]

    def close(self) -> None:
        self.pose.close()


class _Newest:
    """The slot of one picture between the grabber and the landmarker."""

    def __init__(self):
        self._cond = threading.Condition()
        self._item = None
        self.closed = False
        self.skipped = 0

    def put(self, item, wait: bool, stop: threading.Event) -> None:
        """Replace what waits (counted as skipped), or with ``wait`` wait until it is
        taken (every picture of a video looked at: tests, not live)."""
        with self._cond:
            while wait and self._item is not None and not stop.is_set():
                self._cond.wait(0.05)
            if self._item is not None:
                self.skipped += 1
            self._item = item
            self._cond.notify_all()

    def take(self, stop: threading.Event):
        """The newest item, waiting for one; None when closed (or stopped) and empty."""
        with self._cond:
            while self._item is None:
                if self.closed or stop.is_set():
                    return None
                self._cond.wait(0.05)
            item, self._item = self._item, None
            self._cond.notify_all()
            return item

    def close(self) -> None:
        with self._cond:
            self.closed = True
            self._cond.notify_all()


class CameraSource(OscSource):
    """A live source of a camera (``webcam:N``) or a video (``video:PATH``) through a
    pose landmarker; drained, fed, shown and recorded as an ``OscSource``.
    ``open_capture(kind, where, name)`` and ``make_landmarker(name)`` are OpenCV's and
    MediaPipe's unless a test gives others. ``realtime=False``: a video's every picture
    is looked at, as fast as the landmarker goes, each arriving at its time in the
    video (from ``clock()`` at the start), so what comes out does not depend on speed."""

    def __init__(self, spec: str, retargeter=None, guard=None, smoother=None,
                 lost_after: float = LOST_AFTER, clock: Callable[[], float] = time.perf_counter,
                 realtime: bool = True, open_capture=OpenCvCapture,
                 make_landmarker=PoseLandmarker):
        super().__init__("mediapipe-osc", retargeter=retargeter, lost_after=lost_after,
                         clock=clock, guard=guard, smoother=smoother)
        self.kind, self.where = parse_camera(spec)
        self.spec = spec
        self.format = self.kind
        self.decoder = MediaPipeBridgeDecoder(mirrored=False)
        self.queue.name = f"mocap {spec}"
        self.realtime = realtime
        self.open_capture, self.make_landmarker = open_capture, make_landmarker
        self.capture = self.landmarker = None
        self.pictures = 0  # grabbed
        self.looked = 0  # landmarked
        self.ended = threading.Event()  # the video's end, a camera gone, or closed
        self.problem = ""  # why it ended early (a camera gone, the landmarker failed)
        self._slot = _Newest()
        self._threads: list[threading.Thread] = []

    @property
    def skipped_pictures(self) -> int:
        return self._slot.skipped

    def where_text(self, short: bool = False) -> str:
        return str(self.where)  # "mocap webcam 0", "mocap video PATH"

    def listening_line(self) -> str:
        size = "x".join(map(str, getattr(self.capture, "size", ()))) or "?"
        return (f"mocap: reading {self.spec} ({size}, "
                f"{getattr(self.capture, 'fps', 0):.0f} fps) through MediaPipe's pose "
                f"landmarker")

    # -- the landmarker's work (its thread; a test may call it directly)
    def look(self, picture, arrival: float | None = None) -> int:
        """Landmark one RGB picture and receive the pose (or the "no pose") as the
        bridge's message; returns how many samples were posted (0 or 1)."""
        marks = self.landmarker(picture)
        self.looked += 1
        if marks is None:
            return self.receive(encode_pose(None), arrival)
        height, width = picture.shape[:2]
        stretch = (width / height) / ASPECT if height else 1.0
        points = {name: (0.5 + (x - 0.5) * stretch, y, z, seen)
                  for name, (x, y, z, seen) in zip(LANDMARKS, marks)}
        return self.receive(encode_pose(points, mirrored=False), arrival)

    def open(self) -> CameraSource:
        """Open the capture and the landmarker (each a one-line error if it cannot)."""
        if self.capture is None:
            self.capture = self.open_capture(self.kind, self.where, self.spec)
        if self.landmarker is None:
            try:
                self.landmarker = self.make_landmarker(self.spec)
            except BaseException:
                self.capture.release()
                self.capture = None
                raise
        return self

    def start(self) -> CameraSource:
        self.open()
        self._stop.clear()
        self._threads = [threading.Thread(target=self._grab, name=f"grab-{self.kind}",
                                          daemon=True),
                         threading.Thread(target=self._landmark, name=f"pose-{self.kind}",
                                          daemon=True)]
        for thread in self._threads:
            thread.start()
        return self

    def _grab(self) -> None:
        capture, stop = self.capture, self._stop
        start, k, failing = self.clock(), 0, None
        try:
            while not stop.is_set():
                picture = capture.read()
                if picture is None:
                    if getattr(capture, "is_video", True):
                        break  # the video's end
                    now = self.clock()
                    failing = now if failing is None else failing
                    if now - failing > CAMERA_GIVES_UP:
                        self.problem = "the camera stopped giving pictures"
                        break
                    stop.wait(0.01)
                    continue
                failing = None
                due = start + k / capture.fps
                k += 1
                if getattr(capture, "is_video", False):
                    if self.realtime:  # a video plays at its frame rate
                        stop.wait(max(0.0, due - self.clock()))
                        arrival = self.clock()
                    else:
                        arrival = due
                else:
                    arrival = self.clock()
                self.pictures += 1
                self._slot.put((picture, arrival), wait=not self.realtime, stop=stop)
        except Exception as exc:  # noqa: BLE001 - a live source never stops the app
            self.problem = f"reading pictures failed: {type(exc).__name__}: {exc}"
        finally:
            self._slot.close()

    def _landmark(self) -> None:
        try:
            while True:
                item = self._slot.take(self._stop)
                if item is None:
                    break
                picture, arrival = item
                self.look(picture, arrival)
        except Exception as exc:  # noqa: BLE001
            self.problem = f"the pose landmarker failed: {type(exc).__name__}: {exc}"
        finally:
            self.ended.set()

    def status(self, now: float | None = None) -> str:
        text = super().status(now)
        text += f", {self.looked} pictures looked at"
        if self.skipped_pictures:
            text += f", {self.skipped_pictures} skipped"
        if self.ended.is_set():
            text += f", ended ({self.problem})" if self.problem else ", ended"
        return text

    def close(self) -> None:
        self._stop.set()
        self._slot.close()
        for thread in self._threads:
            thread.join(timeout=5.0)
        if any(thread.is_alive() for thread in self._threads):
            return  # stuck in OpenCV or MediaPipe: left to the process's end (daemons)
        self._threads = []
        for part in (self.landmarker, self.capture):
            closing = getattr(part, "close", None) or getattr(part, "release", None)
            if closing is not None:
                with contextlib.suppress(Exception):
                    closing()
        self.landmarker = self.capture = None
        self.ended.set()
