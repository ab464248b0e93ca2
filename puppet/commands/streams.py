"""Live motion-capture streams named on the command line: ``--mocap udp://HOST:PORT``,
``--mocap webcam:N`` and ``--mocap video:PATH`` (play) and ``--mapping`` (play, mocap
send and listen) made into a source.

Nothing but the data layer's errors is imported at the top: the command line starts
fast; each function imports what it needs.
"""

from __future__ import annotations

from puppet.data.errors import UsageError

FORMATS = ("vmc", "mediapipe", "mediapipe-osc", "puppet")  # formats.FORMATS, importless

STREAM_MAPPINGS = {"vmc": "vmc-humanoid", "mediapipe": "mediapipe-pose",
                   "mediapipe-osc": "mediapipe-image"}  # the defaults
POINT_WORDS = {"vmc": "Unity humanoid bone names", "mediapipe": "MediaPipe landmark names",
               "mediapipe-osc": "MediaPipe landmark names"}


def stream_points(fmt: str) -> set[str]:
    """The point names a stream of ``fmt`` can send."""
    if fmt == "vmc":
        from puppet.mocap.unity import PARENTS

        return set(PARENTS)
    from puppet.mocap.mediapipe import LANDMARKS

    return set(LANDMARKS)


def retargeter_for(mapping: str | None):
    """A Retargeter for ``--mapping NAME`` (a catalog name or a path; None without)."""
    if mapping is None:
        return None
    from puppet.data.catalog import find
    from puppet.mocap.retarget import Retargeter, load_mapping

    return Retargeter(load_mapping(find("mapping", mapping)))


CAMERA_KINDS = ("webcam", "video")  # camera.KINDS, importless


def is_camera(value: str | None) -> bool:
    """``--mocap webcam:N`` or ``--mocap video:PATH`` (camera.is_camera, importless)."""
    return bool(value) and ":" in value and value.split(":", 1)[0] in CAMERA_KINDS


def source_for(url: str, fmt: str, mapping: str | None, setup=None, option: str = "--mocap",
               **camera):
    """An (unstarted) OscSource for ``--mocap udp://HOST:PORT``, or a CameraSource for
    ``--mocap webcam:N`` or ``video:PATH`` (MediaPipe's picture landmarks, read as the
    ``mediapipe-osc`` format's: ``fmt`` is not used; ``camera``: CameraSource's test
    options). The points of a vmc or mediapipe stream go through ``mapping`` (a catalog
    name or a path), by default the format's shipped one (``STREAM_MAPPINGS``): a clip's
    mapping (the interface's ``tracking.mapping``) names the clip's joints, which a
    stream does not send."""
    if is_camera(url):
        from puppet.mocap.camera import CameraSource, parse_camera

        parse_camera(url, option)  # a usage error before the mapping is read
        retargeter, guard, smoother = _pipeline("mediapipe-osc", mapping, setup, option)
        return CameraSource(url, retargeter=retargeter, guard=guard, smoother=smoother,
                            **camera)
    from puppet.mocap.formats import decoder, parse_udp
    from puppet.mocap.source import OscSource

    host, port = parse_udp(option, url, decoder(fmt).default_port, listening=True)
    retargeter, guard, smoother = _pipeline(fmt, mapping, setup, option)
    return OscSource(fmt, host, port, retargeter=retargeter, guard=guard, smoother=smoother)


def _pipeline(fmt: str, mapping: str | None, setup, option: str):
    """(retargeter, guard, smoother) of a stream of ``fmt``: what its points go through."""
    retargeter = None
    if fmt != "puppet":
        retargeter = retargeter_for(mapping or STREAM_MAPPINGS[fmt])
        vocabulary = stream_points(fmt)
        foreign = sorted(retargeter.point_names - vocabulary)
        if foreign:
            raise UsageError(f"--mapping {mapping}: reads points a {fmt} stream never sends "
                             f"({', '.join(foreign[:4])}{'...' if len(foreign) > 4 else ''}); "
                             f"expected {POINT_WORDS[fmt]} (e.g. the shipped "
                             f"{STREAM_MAPPINGS[fmt]})")
    elif mapping is not None:
        raise UsageError(f"{option}: a puppet stream sends channels: it needs no --mapping")
    guard = smoother = None
    if setup is not None:  # every sample judged against the figure it drives, then filtered
        from puppet.mocap.guard import guard_for
        from puppet.mocap.smoothing import StreamFilter

        mapping = retargeter.mapping if retargeter is not None else None
        guard = guard_for(setup, mapping)
        smoother = StreamFilter(*((mapping.filter.cutoff, mapping.filter.beta)
                                  if mapping is not None else ()))
    return retargeter, guard, smoother


def is_live(value: str | None) -> bool:
    """``--mocap`` names a live stream (udp://HOST:PORT, any URL, so that tcp://...
    is told what is supported; webcam:N, video:PATH), not a clip."""
    return bool(value) and ("://" in value or is_camera(value))
