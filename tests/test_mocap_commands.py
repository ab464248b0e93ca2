"""``puppet mocap send`` / ``listen`` and ``puppet play --mocap udp://...``, in-process:
what they send, print and refuse (formats, ports, durations, bone tables, mappings a
stream cannot feed), and the files they find from any folder."""

from __future__ import annotations

from pathlib import Path

import pytest

from puppet.data.errors import DataError, UsageError

WALK = "assets/mocap/cmu-131_01-walk.bvh"


ROOT = Path(__file__).resolve().parents[1]


def test_send_counts_what_it_sent_and_refuses_an_unknown_format(capsys):
    from puppet.commands import main

    assert main(["mocap", "send", WALK, "--to", "udp://127.0.0.1:9", "--speed", "10"]) == 0
    out = capsys.readouterr().out
    assert out.rstrip().endswith("frames sent") and "\r" in out
    with pytest.raises(SystemExit) as info:
        main(["mocap", "send", WALK, "--format", "morse"])
    assert info.value.code == 2
    assert "invalid choice: 'morse'" in capsys.readouterr().err


def test_send_takes_a_clip_name_as_mocap_info_does_and_says_it_is_send(capsys):
    from puppet.commands import main

    assert main(["mocap", "send", "cmu-131_01-walk", "--to", "udp://127.0.0.1:9",
                 "--speed", "10", "--quiet"]) == 0
    assert main(["mocap", "send", "cmu-131_01-walk", "--to", "udp://127.0.0.1:9",
                 "--speed", "10"]) == 0
    assert capsys.readouterr().out.startswith("sending cmu-131_01-walk.bvh (")
    assert main(["mocap", "send", "nosuch-walk"]) == 2
    assert capsys.readouterr().err == ("puppet mocap send: nosuch-walk: no clip named "
                                       "'nosuch-walk'; known: cmu-01_01-jumps, "
                                       "cmu-131_01-walk-in-place, cmu-131_01-walk\n")
    assert main(["mocap", "send", "gone/walk.bvh"]) == 2
    assert capsys.readouterr().err.startswith("puppet mocap send: gone/walk.bvh: no such "
                                              "file")


def test_a_headless_live_take_ends_with_the_figures_state_line(tmp_path, capsys):
    from puppet.commands import main

    code = main(["play", "biped-mocap", "--mocap", "udp://127.0.0.1:0", "--headless",
                 "--seconds", "0.2", "--no-record"])
    assert code == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    assert last.startswith("t=0.2") and "com=(" in last and "state=" in last


def test_a_bone_table_that_is_not_a_table_is_a_one_line_error_at_its_start(tmp_path):
    from puppet.data.yamlfile import load_file
    from puppet.mocap.send import parse_bones

    path = tmp_path / "bones.yaml"
    path.write_text("- Hips\n- Chest\n")
    with pytest.raises(DataError) as info:
        parse_bones(load_file(path))
    msg = str(info.value)
    assert msg.startswith(f"{path}:1:") and "\n" not in msg
    assert "a bone table is a mapping with unit, up, vmc and mediapipe" in msg


def test_a_default_file_is_found_from_any_folder(tmp_path, monkeypatch):
    from puppet.commands.mocap import DEFAULT_BONES, _project_file

    monkeypatch.chdir(tmp_path)
    got = _project_file(DEFAULT_BONES)
    assert got.is_absolute() and got.is_file() and got == ROOT / DEFAULT_BONES
    assert _project_file("no/such/file.yaml") == Path("no/such/file.yaml")


def test_a_live_mapping_that_reads_points_the_stream_never_sends_is_refused():
    from puppet.commands.streams import source_for

    with pytest.raises(UsageError) as info:
        source_for("udp://127.0.0.1:0", "vmc", "cmu-131")
    msg = str(info.value)
    assert "reads points a vmc stream never sends" in msg and "Unity humanoid bone names" in msg
    source = source_for("udp://127.0.0.1:0", "vmc", None)  # the shipped vmc-humanoid
    assert source.retargeter is not None


def test_the_listen_help_says_where_the_take_comes_from(capsys):
    from puppet.commands import main

    with pytest.raises(SystemExit):
        main(["mocap", "listen", "--help"])
    out = " ".join(capsys.readouterr().out.split())
    assert "network)" in out


def test_a_listen_duration_is_more_than_zero_and_at_most_a_day():
    import argparse

    from puppet.commands.mocap import _duration

    assert _duration("60") == 60.0 and _duration("86400") == 86400.0
    for bad in ("0", "-1", "86401", "soon"):
        with pytest.raises(argparse.ArgumentTypeError):
            _duration(bad)


def test_listen_listens_on_the_port_it_is_given(capsys):
    import socket

    from puppet.commands import main

    for _ in range(5):  # a free port, probed; another process may take it before the bind
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
            probe.bind(("127.0.0.1", 0))
            port = probe.getsockname()[1]
        code = main(["mocap", "listen", "--format", "puppet", "--port", str(port),
                     "--seconds", "0.1"])
        out, err = capsys.readouterr()
        if code == 0 or "cannot listen" not in err:
            break
    assert code == 0, err
    assert f"listening for puppet on udp://127.0.0.1:{port}" in out


def test_listen_on_port_0_says_the_port_the_system_chose(capsys):
    from puppet.commands import main

    assert main(["mocap", "listen", "--format", "puppet", "--port", "0",
                 "--seconds", "0.1"]) == 0
    line = capsys.readouterr().out.splitlines()[0]
    assert line.startswith("listening for puppet on udp://127.0.0.1:")
    assert int(line.split(":")[2].split(";")[0]) > 0


def test_listen_prints_the_channels_that_arrive(capsys, monkeypatch):
    import socket
    import threading
    import time

    from helpers import ListenedPort

    from puppet.commands import main
    from puppet.mocap.puppet_osc import encode_frame

    listened = ListenedPort(monkeypatch)  # port 0: the system picks a free one
    codes = []
    listener = threading.Thread(target=lambda: codes.append(main(
        ["mocap", "listen", "--format", "puppet", "--port", "0", "--seconds", "0.6"])))
    listener.start()
    port = listened.wait()
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as send:  # a stream, until it
        k = 0                                                        # has listened 0.6 s
        while listener.is_alive() and k < 3000:
            send.sendto(encode_frame(k / 60, {"hip": 0.125}), ("127.0.0.1", port))
            k += 1
            time.sleep(0.01)
    listener.join(5)
    assert codes == [0]
    assert "  channels: hip=0.125" in capsys.readouterr().out
