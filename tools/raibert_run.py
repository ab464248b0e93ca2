"""A Raibert-style run for interfaces/biped-auto.yaml (issue 27, helper run8a): writes the
interface with its run states (run_X, rpush_X, fly_X; poses run_stance, run_push,
run_fly; modes driving, flying) rebuilt from a dict of numbers, the walk left as it is,
and measures what a run looks like. Why a script: the search that found the candidate in
assets/tune/biped-auto-run8a/ varied the structure's numbers together (the same numbers
on both legs' states), which a tuning spec can say only one path at a time.

    python tools/raibert_run.py assets/tune/biped-auto-run8a/candidate.params.json OUT.yaml
    python tools/raibert_run.py PARAMS.json OUT.yaml --measure   # + the look on 3 physics

The controller (Raibert 1986; SIMBICON's stance hip, Yin 2007):
- attitude: in the stance the stance hip holds the pelvis at a forward lean in the world
  (hold: parent) with the pelvis's spin damped in the world and the swing hip's reaction
  taken over (guide 9.8); the waist holds the chest leaning forward in the world;
- thrust: the push-off (run_push: knee straightens, toe points) starts when the stance
  thigh has swept behind the vertical (a role stance_thigh), the clock only a fallback;
  a foot that bounces off after landing (stance foot off for `bounce` s) is a flight;
- speed: in the flight the swing thigh goes to a touch-down angle from com.vx - nearer
  when slower than the desired speed, further when faster (clamped below `vlo`);
- arms from the other side's thigh, the elbows bent; a swing foot that lands before the
  stance foot left (a grounded step) swaps the legs.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BASE = ROOT / "interfaces" / "biped-auto.yaml"

DEFAULT = dict(
    lean=-14.0,          # pelvis held in the world in stance (deg, - forward)
    chest=-14.0,         # chest held in the world by the waist
    spin=0.04,           # pelvis spin damping map on the stance hip (deg per deg/s)
    take=-0.02,          # swing hip torque take-over on the stance hip (deg per N*m)
    swing_cap=250.0, swing_knee_cap=428.0, swing_k=1000.0, swing_knee_k=1000.0,
    trail_k=1000.0, fly_swing_k=1000.0, hold_k=1000.0, hold_d=20.0,
    hip_cap=330.0, knee_cap=428.0, ankle_cap=226.911,
    st_knee=-22.0, st_knee_k=600.0, st_ankle=6.0, st_ankle_k=600.0,
    drive=38.0,          # swing thigh driven forward in stance (world deg)
    drive_knee=-105.0,   # swing knee tucked in stance
    swing_d=8.0,
    push_thigh=-12.0,    # stance thigh behind vertical: thrust
    stance_max=0.3,
    push_knee=-4.0, push_ankle=-30.0, push_k=900.0,
    grounded_after=0.02, lift_after=0.03, push_max=0.12,
    land=18.0,           # neutral touch-down thigh angle in the world at v0
    v0=2.7,              # desired speed
    kv=8.0,              # deg per m/s of (vx - v0), above v0
    kv_lo=8.0,           # deg per m/s below v0 (clamped at vlo)
    vlo=1.0,
    kd=0.0,              # c_d on com.dx.stance_foot in flight
    fly_swing_d=40.0, fly_knee_d=20.0, fly_knee=-25.0, trail_knee=-95.0, trail_hip=-10.0,
    elbow=90.0, arms=0.8,
    rate=480,
    over=None,           # run_X's stance pose travels there over this many s (the landing)
    land_t=None,         # a landing state land_X this long before run_X (None: none)
    land_k=300.0, land_d=60.0,  # its stance knee: soft spring at the landing knee, damped
    push_knee_cap=None, push_ankle_cap=None,  # the push-off's torque caps (None: the stance's)
)

def render(p: dict, base: str | None = None) -> str:
    """The interface's text with the run rebuilt from ``p`` (DEFAULT's keys)."""
    p = {**DEFAULT, **p}

    def f(k):
        return repr(round(float(p[k]), 4))

    trail = '' if p.get('fly_hold') else f" stance_hip: {{world: {f('trail_hip')}}},"
    trail_k = '' if p.get('fly_hold') else f"stance_hip: {f('trail_k')}, "
    land_pose = '' if p.get('land_t') is None else (
        f"  run_land:\n    description: \"the touch-down: the stance knee held soft and damped at the angle it lands with, the foot flat, before the spring\"\n"
        f"    joints: {{stance_knee: {f('fly_knee')}, stance_ankle: {{world: 0}}}}\n"
        f"    stiffness: {{stance_knee: {f('land_k')}, stance_ankle: 800}}\n"
        f"    damping: {{stance_knee: {f('land_d')}}}\n")
    caps = {j: p.get(k) for j, k in (("stance_knee", "push_knee_cap"), ("stance_ankle", "push_ankle_cap"))
            if p.get(k) is not None}
    push_caps = ("    max_torque: {" + ", ".join(f"{j}: {v!r}" for j, v in caps.items()) + "}\n") if caps else ''
    poses = f"""  run_stance:
    description: "the run's stance: the leg a spring under a trunk held leaning forward in the world, the swing thigh driven forward and its knee tucked, the elbows bent"
    joints: {{waist: {{world: {f('chest')}}}, stance_knee: {f('st_knee')}, stance_ankle: {f('st_ankle')},
             swing_hip: {{world: {f('drive')}}}, swing_knee: {f('drive_knee')}, swing_ankle: {{world: 0}},
             elbow_near: {f('elbow')}, elbow_far: {f('elbow')}}}
    stiffness: {{stance_hip: {f('hold_k')}, stance_knee: {f('st_knee_k')}, stance_ankle: {f('st_ankle_k')}, swing_ankle: 800, swing_hip: {f('swing_k')}, swing_knee: {f('swing_knee_k')}}}
    damping: {{stance_hip: {f('hold_d')}, stance_knee: 50, stance_ankle: 30,
              swing_hip: {f('swing_d')}, swing_knee: 8, swing_ankle: 3}}
    max_torque: {{stance_hip: {f('hip_cap')}, swing_hip: {f('swing_cap')}, stance_knee: {f('knee_cap')},
                 swing_knee: {f('swing_knee_cap')}, stance_ankle: {f('ankle_cap')}, swing_ankle: {f('ankle_cap')}}}
{land_pose}  run_push:
    description: "the run's thrust: once the stance thigh is behind the body the knee straightens and the toe points"
    joints: {{stance_knee: {f('push_knee')}, stance_ankle: {f('push_ankle')}}}
    stiffness: {{stance_knee: {f('push_k')}, stance_ankle: {f('push_k')}}}
{push_caps}  run_fly:
    description: "the flight: the trailing knee folds, the leading leg opens to land where the speed says"
    joints: {{swing_knee: {f('fly_knee')}, stance_knee: {f('trail_knee')},{trail}
             stance_ankle: {{world: 0}}}}
    stiffness: {{{trail_k}stance_ankle: 800, swing_hip: {f('fly_swing_k')}, swing_knee: 1000}}
    damping: {{stance_hip: 20, swing_hip: {f('fly_swing_d')}, swing_knee: {f('fly_knee_d')}}}
"""
    lean_map = (f"    - {{input: mouse.x, joint: stance_hip, from: [0.68, 1], to: [{f('lean')}, {f('lean')}], frame: world,\n"
                f"       hold: parent, description: \"mouse x (run): the pelvis held leaning forward in the world\"}}\n")
    arms = (f"    - {{input: sensor.angle.swing_thigh, joint: stance_shoulder, from: [0, 1],\n"
            f"       to: [0, {f('arms')}], clamp: false, combine: add, description: arms swing opposite the legs}}\n"
            f"    - {{input: sensor.angle.swing_thigh, joint: swing_shoulder, from: [0, 1],\n"
            f"       to: [0, {-p['arms']!r}], clamp: false, combine: add, description: ... the other way}}\n")
    lo = p['land'] - p['kv_lo'] * (p['v0'] - p['vlo'])
    modes = f"""  driving:
{lean_map}    - {{input: sensor.spin.pelvis, joint: stance_hip, from: [0, 1], to: [0, {f('spin')}], clamp: false,
       combine: add, description: "the pelvis's spin damped in the world (SIMBICON)"}}
    - {{input: sensor.torque.swing_hip, joint: stance_hip, from: [0, 1], to: [0, {f('take')}], clamp: false,
       combine: add, description: "the swing hip's reaction taken over by the stance hip (SIMBICON)"}}
{arms}  flying:
{lean_map if p.get('fly_hold') else ''}    - {{input: sensor.com.vx, joint: swing_hip, from: [{f('vlo')}, {f('v0')}], to: [{lo!r}, {f('land')}], frame: world,
       description: "Raibert: the touch-down thigh angle - nearer when slower than the desired speed"}}
    - {{input: sensor.com.vx, joint: swing_hip, from: [{f('v0')}, {p['v0'] + 1!r}], to: [0, {f('kv')}], clamp: false,
       combine: add, description: "... further when faster"}}
    - {{input: sensor.com.dx.stance_foot, joint: swing_hip, from: [0, 1], to: [0, {f('kd')}], clamp: false,
       combine: add, description: swing foot further the more ahead}}
{arms}"""
    def bounce(X):
        if p.get('bounce') is None:
            return ''
        return (f"\n      - {{to: fly_{X}, after: 0.02, when: {{sensor: contact.stance_foot, is: false}}, for: {p['bounce']!r}}}"
                "   # bounced off: a flight")
    over = '' if p.get('over') is None else f", over: {f('over')}"
    def land(X):
        if p.get('land_t') is None:
            return ''
        return f"""  land_{X}:
    roles: {X}
    control_rate: {p['rate']}
    enter: {{pose: run_land, mode: driving}}
    transitions:
      - {{to: on_{X}, when: {{sensor: input.mouse.x, below: 0.66}}}}   # back to the walk
      - {{to: run_{X}, after: {f('land_t')}}}
"""
    def st(X, Y):
        tgt = f"land_{Y}" if p.get('land_t') is not None else f"run_{Y}"
        return land(X) + f"""  run_{X}:
    roles: {X}
    control_rate: {p['rate']}
    enter: {{pose: run_stance, mode: driving{over}}}
    transitions:
      - {{to: on_{X}, when: {{sensor: input.mouse.x, below: 0.66}}}}   # back to the walk
      - {{to: rpush_{X}, after: 0.03, when: [{{sensor: angle.stance_thigh, below: {f('push_thigh')}}}, {{sensor: contact.stance_foot, is: true}}]}}
      - {{to: rpush_{X}, after: {f('stance_max')}}}{bounce(X)}
  rpush_{X}:
    roles: {X}
    control_rate: {p['rate']}
    enter: {{pose: run_push}}
    transitions:
      - {{to: fly_{X}, after: {f('lift_after')}, when: {{sensor: contact.stance_foot, is: false}}, for: 0.01}}
      - {{to: run_{Y}, after: {f('grounded_after')}, when: {{sensor: contact.swing_foot, is: true}}}}   # landed before a flight: a grounded step
      - {{to: fly_{X}, after: {f('push_max')}}}
  fly_{X}:
    roles: {X}
    control_rate: {p['rate']}
    enter: {{pose: run_fly, mode: flying}}
    transitions:
      - {{to: {tgt}, when: {{sensor: contact.swing_foot, is: true}}, after: 0.0}}
"""
    text = base if base is not None else BASE.read_text(encoding="utf-8")
    text = text.replace("  swing_shoulder:  {near: shoulder_far,  far: shoulder_near}\n",
                        "  swing_shoulder:  {near: shoulder_far,  far: shoulder_near}\n"
                        "  stance_thigh:    {near: thigh_near,    far: thigh_far}\n")
    a, b = text.index("  run_stance:\n"), text.index("modes:\n")
    text = text[:a] + poses + text[b:]
    a, b = text.index("  driving:\n"), text.index("initial: standing")
    text = text[:a] + modes + text[b:]
    a = text.index("  run_near:\n")
    text = text[:a] + st("near", "far") + st("far", "near")
    return text

def look(traj, t0: float = 20.0) -> dict:
    """What the run looks like from ``t0`` on: the trunk's mean lean (deg, - forward),
    the flights (no link touching: how many, median length, median height the lower foot
    rose from the take-off), the elbows' mean bend and the stance thigh's range."""
    import numpy as np

    w = traj.t >= t0
    out = {n: round(float(np.degrees(traj.angle[w, traj.index(n)]).mean()), 1)
           for n in ("pelvis", "chest")}
    free = ~traj.contact.any(axis=1) & w
    edges = np.diff(np.concatenate(([0], free.astype(np.int8), [0])))
    spans = list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)))
    feet = [traj.index("foot_near"), traj.index("foot_far")]
    durs = [float(traj.t[min(b, len(traj.t) - 1)] - traj.t[a]) for a, b in spans]
    clear = [float(traj.lowest[a:b][:, feet].min(axis=1).max() - traj.lowest[a, feet].min())
             for a, b in spans]
    out["flights"] = len(spans)
    out["flight_s"] = round(float(np.median(durs)), 3) if durs else 0.0
    out["clear_cm"] = round(100 * float(np.median(clear)), 1) if clear else 0.0
    j = traj.joints
    out["elbow"] = round(float(np.degrees(traj.joint_angle[w][:, [j.index("elbow_near"),
                                                                   j.index("elbow_far")]]).mean()))
    th = np.degrees(traj.angle[w, traj.index("thigh_near")])
    out["thigh_5_95"] = [round(float(np.percentile(th, q))) for q in (5, 95)]
    return out


def measure(interface: Path) -> dict:
    """The log's script (biped-auto-run) played through ``interface``, replayed on the
    shipped physics, 36 solver passes and a 1/240 s step: the sidecar's failures, the
    speed over the last 5 s and the look."""
    import shutil
    import tempfile

    from puppet.testing import record_script
    from puppet.timeline.log import read_log
    from puppet.timeline.other_physics import OtherPhysics
    from puppet.timeline.replay import replay

    physics = {"40 passes": None, "36 passes": OtherPhysics(iterations=36),
               "1/240 s": OtherPhysics(dt=1 / 240)}
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        log = Path(tmp) / "c.jsonl"
        record_script("biped-auto-run", log, interface=str(interface))
        shutil.copy(ROOT / "assets" / "logs" / "biped-auto-run.expect.yaml",
                    Path(tmp) / "c.expect.yaml")
        for name, ph in physics.items():
            r = replay(read_log(log), physics=ph)
            tr = r.trajectory
            w = tr.t >= 25
            v = (tr.com[w][-1, 0] - tr.com[w][0, 0]) / (tr.t[w][-1] - tr.t[w][0])
            out[name] = {"m/s": round(float(v), 2), "failed": [o.kind for o in r.failed],
                         **look(tr)}
    return out


def main(argv: list[str]) -> int:
    if len(argv) < 2:
        print("usage: raibert_run.py PARAMS.json OUT.yaml [--measure]", file=sys.stderr)
        return 2
    params = json.loads(Path(argv[0]).read_text(encoding="utf-8"))
    Path(argv[1]).write_text(render(params), encoding="utf-8")
    if "--measure" in argv[2:]:
        for name, row in measure(Path(argv[1])).items():
            print(name, row)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
