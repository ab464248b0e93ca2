"""The bench's report as a person reads it: one row per figure, its target and
PASS/MISS, and the targets missed at the end."""

from __future__ import annotations

from puppet.commands.bench.config import PROCESS_TARGET_MS


def _fmt_bytes(n: float) -> str:
    for unit in ("B", "kB", "MB", "GB"):
        if abs(n) < 1000 or unit == "GB":
            return f"{n:.0f} {unit}" if unit == "B" else f"{n:.1f} {unit}"
        n /= 1000.0
    return f"{n}"


def format_report(report: dict) -> str:
    cfg = report["config"]
    lines = [f"puppet bench{' --quick' if report['quick'] else ''}: pymunk {report['pymunk']}, "
             f"Python {report['python']}, dt = 1/{round(1 / report['dt'])} s, input every "
             f"1/{report['frame_hz']:.0f} s, rendering off; medians of {cfg['repeats']} runs "
             f"of {cfg['seconds']:g} simulated s"
             + ("; times are the thread's CPU time (--cpu)"
                if report.get("clock") == "cpu" else "")]

    def row(label, value, target="", verdict=""):
        lines.append(f"  {label:<44} {value:>12}  {target:<10} {verdict}")

    for c in report["characters"]:
        cp, rw = c["checkpoint"], c["rewind"]
        verdict = {t["name"]: ("PASS" if t["pass"] else "MISS") for t in c["targets"]}
        limit = {t["name"]: f"{t['op']} {t['limit']:g}{' ' if t['unit'] == 'ms' else ''}"
                             f"{t['unit']}" for t in c["targets"]}
        lines.append("")
        step = (f", its own step 1/{round(1 / c['dt'])} s"
                if c.get("dt") and c["dt"] != report["dt"] else "")  # (solver: {step})
        lines.append(f"{c['character']} ({c['bodies']} bodies, {c['constraints']} "
                     f"constraints{step})")
        for entry in c["interfaces"]:
            sp, name = entry["speed"], entry["interface"] or "no interface"
            lines.append(f" via {name} on {entry['scene']}")
            row("speed with control (Session, real time = 1x)",
                f"{sp['control_speed_x']:.0f}x", limit[f"speed with control: {name}"],
                verdict[f"speed with control: {name}"])
            row("bare space.step, same motion", f"{sp['bare_same_motion_speed_x']:.0f}x")
            lo, hi = sp["control_overhead_range_pct"]
            row(f"control overhead vs same motion ({lo:.0f}..{hi:.0f}%)",
                f"{sp['control_overhead_pct']:.1f}%",
                limit[f"control overhead: {name}"], verdict[f"control overhead: {name}"])
            row("  per frame: control / bare", f"{sp['control_us_per_frame']:.1f}/"
                f"{sp['bare_us_per_frame']:.1f} us")
            row("  same trajectory (state hash)",
                "identical" if sp["same_motion_state_identical"] else "DIFFERENT")
            row("with the timeline's keyframes: speed", f"{sp['with_keyframes_speed_x']:.0f}x")
            row("with the timeline's keyframes: overhead (info)",
                f"{sp['with_keyframes_overhead_pct']:.1f}%")
        lines.append(" timeline")
        row("snapshot size", _fmt_bytes(cp["bytes"]))
        row("snapshot", f"{cp['snapshot_ms']:.3f} ms")
        row("restore", f"{cp['restore_ms']:.3f} ms")
        row("checkpoint (snapshot + re-seat)", f"{cp['checkpoint_ms']:.3f} ms",
            limit["checkpoint"], verdict["checkpoint"])
        row(f"keyframes ({rw['source']}): {rw['entries']} x {rw['interval_s']:g} s",
            _fmt_bytes(rw["keyframe_bytes"]))
        row("tracemalloc over the run: retained / peak",
            f"{_fmt_bytes(rw['traced_current_bytes'])} / "
            f"{_fmt_bytes(rw['traced_peak_bytes'])}")
        row("speed with control + history", f"{rw['control_with_history_speed_x']:.0f}x")
        row(f"rewind {rw['rewound_s']:.1f} s (re-simulating {rw['interval_s']:g} s)",
            f"{rw['restore_ms']:.3f} ms")
        row(f"rewind {rw['rewound_s']:.1f} s: that + first frame",
            f"{rw['resume_ms']:.3f} ms", limit["rewind 60 s and resume"],
            verdict["rewind 60 s and resume"])
        sc = c["scrub"]
        row(f"scrub frame ({sc['frames']} frames, {sc['scrubbed_s']:.1f} s back): p50 / p99",
            f"{sc['p50_ms']:.2f} / {sc['p99_ms']:.2f} ms")
        row("scrub frame: worst", f"{sc['max_ms']:.2f} ms", limit["scrub frame, worst"],
            verdict["scrub frame, worst"])
        row("scrub release (the exact rewind)", f"{sc['release_ms']:.2f} ms")
    for ch in report.get("channels", []):
        t = ch["target"]
        lines.append("")
        lines.append(f"input: a {ch['hz']:.0f} Hz stream of {ch['channels']} channels "
                     f"({ch['character']}), against the same targets written directly")
        lo, hi = ch["overhead_range_pct"]
        row(f"channels overhead ({lo:.1f}..{hi:.1f}%)", f"{ch['overhead_pct']:.1f}%",
            f"<= {t['limit']:g}%" if t else "(info)",
            ("PASS" if t["pass"] else "MISS") if t else "")
        row("speed with the stream", f"{ch['speed_x']:.0f}x")
        row("  same trajectory (state hash)",
            "identical" if ch["state_identical"] else "DIFFERENT")
    for fb in report.get("feedback", []):
        t = fb["target"]
        lines.append("")
        lines.append(f"feedback maps ({fb['interface']}): with them against without, the same "
                     "input, in turns")
        lo, hi = fb["overhead_range_pct"]
        row(f"feedback maps cost ({lo:.1f}..{hi:.1f}%)", f"{fb['overhead_pct']:.1f}%",
            f"<= {t['limit']:g}%", "PASS" if t["pass"] else "MISS")
    for g in report.get("grasping", []):
        speed, cp = g["speed"], g["checkpoint"]
        lines.append("")
        lines.append(f"holding on: {g['character']} ({g['interface']}) on {g['scene']}, "
                     f"{len(g['held_at_start'])} grasps ({', '.join(g['held_at_start'])}; "
                     f"{len(g['held_at_end'])} still held after the gesture), "
                     f"{g['dynamic_props']} dynamic props, {g['constraints']} constraints")
        t_speed, t_cp = g["targets"]
        row("speed with control", f"{speed['control_speed_x']:.0f}x",
            f">= {t_speed['limit']:g}x", "PASS" if t_speed["pass"] else "MISS")
        row("  bare space.step, same motion", f"{speed['bare_same_motion_speed_x']:.0f}x"
            + ("" if speed["same_motion_state_identical"] else " (DIFFERENT)"))
        row("checkpoint: snapshot + re-seat", f"{cp['checkpoint_ms']:.2f} ms",
            f"< {t_cp['limit']:g} ms", "PASS" if t_cp["pass"] else "MISS")
    logs = report["logs"]
    lines.append("")
    lines.append(f"log replay (assets/logs/*.jsonl): {logs['status']}")
    for item in logs["items"]:
        if "error" in item:
            lines.append(f"  {item['log']:<44} error: {item['error']}")
        elif item.get("speed_x"):
            lines.append(f"  {item['log']:<44} {item['speed_x']:>11.0f}x  "
                         f"({item['sim_seconds']:.1f} s in {item['wall_s'] * 1e3:.0f} ms)")
        elif "wall_s" in item:
            lines.append(f"  {item['log']:<44} {item['wall_s'] * 1e3:>9.0f} ms")
    items = [i for i in logs["items"] if i.get("speed_x")]
    if items:
        sim, wall = sum(i["sim_seconds"] for i in items), sum(i["wall_s"] for i in items)
        lines.append(f"  {'all (replayed with their expectations)':<44} "
                     f"{sim / wall:>11.0f}x  ({sim:.1f} s in {wall * 1e3:.0f} ms)")
    lines += format_feats(report["feats"])
    if report.get("hud_frames"):
        lines.append("")
        lines.append("a frame with the HUD and F1 open (1280x720, the log replayed and drawn "
                     "as the window does)")
        for f in report["hud_frames"]:
            t = f["target"]
            row(f"{f['log']} ({f['scene']}): p50 / p99 / worst",
                f"{f['p50_ms']:.1f}/{f['p99_ms']:.1f}/{f['max_ms']:.1f} ms",
                f"p99 <= {t['limit']:g} ms", "PASS" if t["pass"] else "MISS")
            row("  physics p50 / p99; drawing p50 / p99",
                f"{f['physics_p50_ms']:.1f}/{f['physics_p99_ms']:.1f}; "
                f"{f['draw_p50_ms']:.1f}/{f['draw_p99_ms']:.1f} ms")
    pr = report["processes"]
    verdict = {t["name"]: "PASS" if t["pass"] else "MISS" for t in report["targets"]}
    lines.append("")
    lines.append("processes (python -m puppet ..., end to end, medians)")
    lines.append(f"  (CPU ms of each process, user + system, beside; load average "
                 f"{report.get('load_average', '?')})")

    def cpu(name: str) -> str:
        return f" (cpu {pr[name + '_cpu_ms']:.0f})" if name + "_cpu_ms" in pr else ""
    row("startup (--version)", f"{pr['startup_ms']:.0f} ms{cpu('startup')}")
    row("replay luxo-hop --headless", f"{pr['replay_ms']:.0f} ms{cpu('replay')}",
        f"< {PROCESS_TARGET_MS:g} ms", verdict["headless replay process (luxo-hop)"])
    row("check characters/luxo.yaml", f"{pr['check_ms']:.0f} ms{cpu('check')}",
        f"< {PROCESS_TARGET_MS:g} ms", verdict["check process (one file)"])
    if "check_interface_ms" in pr:
        row("check interfaces/luxo-keys.yaml",
            f"{pr['check_interface_ms']:.0f} ms{cpu('check_interface')}",
            f"< {PROCESS_TARGET_MS:g} ms", verdict.get("check process (an interface)", ""))
    lines.append("")
    lines.append("motion capture (assets/mocap/*.bvh)")
    for item, t in zip(report["mocap"]["items"], report["mocap"]["targets"]):
        row(f"read {item['clip']} ({_fmt_bytes(item['bytes'])}, {item['frames']} frames)",
            f"{item['read_ms']:.1f} ms", f"< {t['limit']:g} ms", "PASS" if t["pass"] else "MISS")
        row(f"  forward kinematics, {item['joints']} joints", f"{item['fk_ms']:.1f} ms")
        if "retarget_ms" in item:
            row(f"  retarget ({item['mapping']})", f"{item['retarget_ms']:.1f} ms")
    kd = report["mocap"].get("kd_walk")
    if kd:
        row(f"KD control of the walk clip ({kd['seconds']:.1f} s)",
            f"{kd['kd_speed_x']:.0f}x real time",
            f"{kd['overhead_pct']:+.0f} % over its channels alone ({kd['off_speed_x']:.0f}x)")
    for path, lat in report.get("mocap_latency", {}).items():
        t = lat["target"]
        if "send_median_ms" in lat:
            row(f"mocap-latency ({path}): send -> targets, median / p99",
                f"{lat['send_median_ms']:.1f}/{lat['send_p99_ms']:.1f} ms")
            row("  (with decoding; most frames waiting at a drain, poses skipped)",
                f"{lat['queued_max']}, {lat['skipped']}")
        row(f"mocap-latency ({path}): arrival -> targets", f"{lat['median_ms']:.1f} ms")
        row(f"  99th percentile / worst ({lat['samples']} samples)",
            f"{lat['p99_ms']:.1f}/{lat['max_ms']:.1f} ms")
        row("  acting at the next 60 fps frame", f"{lat['next_frame_pct']:.1f}%",
            f">= {t['limit']:g}%", "PASS" if t["pass"] else "MISS")
        row("  the frame's handling (drain -> targets)", f"{lat['processing_median_ms']:.2f} ms")
    lines.append("")
    misses = [f"{c['character']}: {t['name']}" for c in report["characters"]
              for t in c["targets"] if not t["pass"]] + \
        [t["name"] for t in report["targets"] if not t["pass"]]
    misses += [ch["target"]["name"] for ch in report.get("channels", [])
               if ch["target"] and not ch["target"]["pass"]]
    misses += [f"mocap: {t['name']}" for t in report["mocap"]["targets"] if not t["pass"]]
    misses += [r["target"]["name"] for r in report.get("mocap_latency", {}).values()
               if not r["target"]["pass"]]
    misses += [f["target"]["name"] for f in report.get("feedback", []) if not f["target"]["pass"]]
    misses += [t["name"] for g in report.get("grasping", []) for t in g["targets"]
               if not t["pass"]]
    misses += feat_misses(report["feats"])
    misses += [f["target"]["name"] for f in report.get("hud_frames", [])
               if not f["target"]["pass"]]
    lines.append("all targets met" if not misses else "MISSED: " + "; ".join(misses))
    return "\n".join(lines)


def format_feats(feats: dict) -> list[str]:
    """The feat logs' section: per log the control overhead (median of the rounds,
    their range), the time per step with control and bare, and whether the bare run
    made the same motion."""
    part = f", the first {feats['seconds']:g} s of each" if feats["seconds"] else ""
    title = ("control overhead on the shipped feat logs (with control against bare "
             f"Chipmunk fed the same writes, {feats['rounds']} interleaved rounds{part})")
    columns = (f"  {'log':<34} {'overhead':>8} {'(range)':>14}  "
               f"{'control/bare us a step':>22}  target")
    lines = ["", title, columns]
    verdict = {t["name"]: t for t in feats["targets"]}
    for item in feats["items"]:
        if "error" in item:
            lines.append(f"  {item['log']:<34} error: {item['error']}")
            continue
        t = verdict[f"control overhead: {item['log']}"]
        lo, hi = item["overhead_range_pct"]
        lines.append(f"  {item['log']:<34} {item['overhead_pct']:>7.1f}% "
                     f"{f'({lo:.0f}..{hi:.0f}%)':>14}  "
                     f"{item['control_us_per_step']:>10.1f} / {item['bare_us_per_step']:<9.1f}"
                     f"  <= {t['limit']:g}% {'PASS' if t['pass'] else 'MISS'}"
                     + ("" if item["same_motion"] else "  DIFFERENT MOTION"))
    median = verdict.get("control overhead: median over the feat logs")
    if median:
        lines.append(f"  {'median over the logs':<34} {median['value']:>7.1f}%"
                     f"{'':>41}<= {median['limit']:g}% "
                     f"{'PASS' if median['pass'] else 'MISS'}")
    return lines


def feat_misses(feats: dict) -> list[str]:
    out = [t["name"] for t in feats["targets"] if not t["pass"]]
    out += [f"bare run of {i['log']} made another motion" for i in feats["items"]
            if not i.get("same_motion", True)]
    return out


def format_feat_report(report: dict) -> str:
    """``puppet bench --feats``."""
    lines = [f"puppet bench --feats{' --quick' if report['quick'] else ''}: pymunk "
             f"{report['pymunk']}, Python {report['python']}, dt = 1/{round(1 / report['dt'])}"
             f" s" + ("; times are the thread's CPU time (--cpu)"
                      if report.get("clock") == "cpu" else "")
             + f"; load average {report.get('load_average', '?')}"]
    lines += format_feats(report["feats"])
    misses = feat_misses(report["feats"])
    lines += ["", "all targets met" if not misses else "MISSED: " + "; ".join(misses)]
    return "\n".join(lines)
