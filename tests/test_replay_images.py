"""``puppet replay LOG --headless --frames DIR --screenshot FILE``, as ``play`` has them.

The images are drawn by the code that draws play's (``puppet.app.headless.Images``):
a run recorded by ``play --headless --record`` and its replay write the same pixels,
and the replay still prints its state line (and checks, with --check) unchanged."""

from __future__ import annotations

from pathlib import Path

from puppet.commands import main


def _pngs(folder: Path) -> list[bytes]:
    return [p.read_bytes() for p in sorted(folder.glob("frame_*.png"))]


def test_a_replay_writes_the_frames_and_screenshot_its_recording_wrote(tmp_path, capsys):
    log = tmp_path / "hop.jsonl"
    played, replayed = tmp_path / "played", tmp_path / "replayed"
    assert main(["play", "luxo-keys", "--headless", "--input", "luxo-hop", "--seconds", "1",
                 "--fps", "10", "--record", str(log), "--frames", str(played),
                 "--screenshot", str(tmp_path / "played.png")]) == 0
    play_out = capsys.readouterr().out
    assert main(["replay", str(log), "--headless", "--check", "--fps", "10",
                 "--frames", str(replayed), "--screenshot", str(tmp_path / "replayed.png")]) == 0
    out = capsys.readouterr().out
    assert "(same as recorded)" in out and "ok   same end as the recording" in out, out
    assert f"wrote 10 frames to {replayed}" in out and f"wrote {tmp_path / 'replayed.png'}" in out
    frames = _pngs(replayed)
    assert len(frames) == 10 and frames == _pngs(played)  # pixel for pixel, HUD and all
    assert (tmp_path / "replayed.png").read_bytes() == (tmp_path / "played.png").read_bytes()
    state = play_out.split("state=")[1].split()[0]
    assert f"state={state} (same as recorded)" in out  # the images changed nothing


def test_replay_images_follow_the_log_and_the_options(tmp_path, capsys):
    """--until-step stops the frames there; --size draws a larger window; a frame is the
    HUD's and the world's (not blank)."""
    from PIL import Image

    out_dir = tmp_path / "frames"
    assert main(["replay", "luxo-hop", "--headless", "--until-step", "480", "--fps", "5",
                 "--size", "640x360", "--frames", str(out_dir)]) == 0
    out = capsys.readouterr().out
    assert "step 480" in out and "wrote 5 frames" in out, out
    frames = sorted(out_dir.glob("frame_*.png"))
    assert [p.name for p in frames] == [f"frame_{i:05d}.png" for i in range(5)]
    image = Image.open(frames[-1])
    colours = image.getcolors(1 << 16)
    assert image.size == (640, 360) and colours is not None and len(colours) > 20  # drawn


def test_replay_image_options_are_checked_before_anything_runs(tmp_path, capsys):
    afile = tmp_path / "afile"
    afile.write_text("")
    cases = [
        (("--frames", str(tmp_path / "f")), "puppet replay: --screenshot and --frames need "
                                            "--headless"),
        (("--headless", "--screenshot", str(tmp_path / "x.txt")),
         "puppet replay: --screenshot " + str(tmp_path / "x.txt") + ": '.txt'; give a file "
         "name ending in .png"),
        (("--headless", "--frames", str(afile)), f"puppet replay: --frames {afile}: is a file"),
        (("--headless", "--frames", str(tmp_path / "f"), "--video", str(tmp_path / "v.mp4")),
         "puppet replay: --frames and --screenshot go without --video and --plot"),
        (("--headless", "--screenshot", str(tmp_path / "s.png"), "--export-motion",
          str(tmp_path / "m.csv")), "puppet replay: --export-motion goes alone"),
        (("luxo-backflip", "--headless", "--frames", str(tmp_path / "f")),
         "puppet replay: --frames and --screenshot take one log"),
    ]
    for extra, start in cases:
        code = main(["replay", "luxo-hop", *extra])
        err = capsys.readouterr().err
        assert code == 2 and err.startswith(start) and err.count("\n") == 1, (extra, err)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile"]
