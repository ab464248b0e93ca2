"""The documented biped-walk.yaml from a parameter set (gen8's names)."""
import sys, ast
sys.path.insert(0, "/tmp/walkh")
from walk_params import DEF

def r(v):
    v = round(float(v), 3)
    return int(v) if v == int(v) else v

def walk(p, how, small=False):
    q = dict(DEF); q.update(p); p = q
    g = lambda k: r(p[k])
    lh0, lh1 = r(p['LH'] - p['LHX'] / 2), r(p['LH'] + p['LHX'] / 2)
    lk0, lk1 = r(p['LK'] + p['LKY'] / 2), r(p['LK'] - p['LKY'] / 2)
    rh0, rh1 = r(p['RH'] - p['RHX'] / 2), r(p['RH'] + p['RHX'] / 2)
    le0, le1 = r(p['LEAN'] - p['LEANX'] / 2), r(p['LEAN'] + p['LEANX'] / 2)
    ll0, ll1 = r(p['LEAN'] + p['LEAN_L'] - p['LEANX'] / 2), r(p['LEAN'] + p['LEAN_L'] + p['LEANX'] / 2)
    def lean(a, b):
        return f"""    - {{input: mouse.x, joint: stance_hip, from: [0, 1], to: [{a}, {b}], frame: world,
       hold: parent, description: "mouse x: the pelvis upright .. leaning forward"}}
"""
    def fb(cd, cv):
        return f"""    - {{input: sensor.com.dx.stance_foot, joint: swing_hip, from: [0, 1], to: [0, {r(cd)}],
       clamp: false, combine: add, description: the swing foot further the more the body is ahead}}
    - {{input: sensor.com.vx, joint: swing_hip, from: [0, 1], to: [0, {r(cv)}], clamp: false,
       combine: add, description: ... and the faster it goes}}
"""
    arms = f"""    - {{input: sensor.angle.swing_thigh, joint: stance_shoulder, from: [0, 1],
       to: [0, {g('ARM')}], clamp: false, combine: add, description: the arms swing opposite the legs}}
    - {{input: sensor.angle.swing_thigh, joint: swing_shoulder, from: [0, 1],
       to: [0, {r(-p['ARM'])}], clamp: false, combine: add, description: ... the other way}}
"""
    spd = f"""    - {{input: sensor.com.vx, joint: stance_ankle, from: [{g('SV0')}, {r(p['SV0'] + 1)}], to: [0, {r(-p['SVK'])}], clamp: false,
       combine: add, description: "the stance ankle holds back a body faster than {g('SV0')} m/s, pushes a slower one"}}
""" if p['SVK'] else ""
    ank = f"""    - {{input: sensor.com.dx.stance_foot, joint: stance_ankle, from: [0, 1], to: [0, {g('ANK_D')}],
       clamp: false, combine: add, description: the front ankle holds the body back the further it is ahead}}
    - {{input: sensor.com.vx, joint: stance_ankle, from: [0, 1], to: [0, {g('ANK_V')}], clamp: false,
       combine: add, description: ... and the faster it goes}}
"""
    y = f"""name: biped-walk
description: "{how}"
character: biped
scene: biped-track
slowdown: 3
# The paper's walk (Laszlo et al. 2000): the mouse is where the swing leg lifts to, a key
# swaps the legs. Made forgiving by construction (issue 27, docs/interfaces.md 9.6): the
# balance never hangs on the step a key is pressed at.
#   lift_X   (X: the stance leg) the swing leg lifts to the mouse's place for {g('LIFT_T')} s: mouse x
#            how far the thigh comes forward and the pelvis leans, y how high the knee;
#   reach_X  then reaches down by itself to where the foot catches the body (SIMBICON's
#            placement: {g('CD_R')} deg per m the body is ahead of the stance foot, {g('CV_R')} per m/s);
#   land_Y   the swing foot touching down makes it the stance leg (Y): both feet down for
#            {g('TOE_T')} s while the back foot pushes off and the front ankle holds the body;
#   ready_Y  then space lifts the back leg (lift_Y). A press made any time from the last swap
#            on is kept (buffer) and acts as soon as ready_Y is entered, so a press early in
#            the stride waits for the foot to land and the push-off to end, and a person
#            pressing a reaction time after the foot lands (0.2-0.3 s real at slowdown 3) is
#            on time every step. No press: the figure stays on both feet, the front ankle
#            holding the body (a late press is a pause, not a fall).
# Why this shape: the paper's own swap on a press put the weight on a leg wherever its foot
# was at that step; the recorded walk passed its expectations only at the exact steps of its
# presses (0 of 10 tries at +-10 ms). Here the phases change on sensors (touch-down) and
# timers counted from them, and the press only says "next step".
# Joint signs: hip + swings the thigh forward, knee - bends it, ankle + lifts the toes.
# The swing leg's damping is low ({g('SWING_D')}: pymunk's damping scales with 1/inertia, and the
# light leg could not move quickly at the stance leg's 50). The gains are the character's
# (written out) but the caps of hips ({g('HIPT')} N*m), knees ({g('KNEET')}) and ankles ({g('ANKT')}): a walker's peaks.
# Logs: assets/logs/biped-walk.jsonl (the mouse moving, space every 0.5 s, 10+ m on
# biped-track), biped-march.jsonl (the mouse parked, over biped-terrain) and
# biped-walk-watched (a reactive script: space a person's reaction after each landing).
control_rate: 120
gains:
  ankle_near: {{stiffness: 800, damping: 30, max_torque: {g('ANKT')}}}
  ankle_far: {{stiffness: 800, damping: 30, max_torque: {g('ANKT')}}}
  knee_near: {{stiffness: 1000, damping: 50, max_torque: {g('KNEET')}}}
  knee_far: {{stiffness: 1000, damping: 50, max_torque: {g('KNEET')}}}
  hip_near: {{stiffness: 1000, damping: 50, max_torque: {g('HIPT')}}}
  hip_far: {{stiffness: 1000, damping: 50, max_torque: {g('HIPT')}}}
roles:
  stance_hip:      {{near: hip_near,      far: hip_far}}
  stance_knee:     {{near: knee_near,     far: knee_far}}
  stance_ankle:    {{near: ankle_near,    far: ankle_far}}
  swing_hip:       {{near: hip_far,       far: hip_near}}
  swing_knee:      {{near: knee_far,      far: knee_near}}
  swing_ankle:     {{near: ankle_far,     far: ankle_near}}
  stance_foot:     {{near: foot_near,     far: foot_far}}
  swing_foot:      {{near: foot_far,      far: foot_near}}
  swing_thigh:     {{near: thigh_far,     far: thigh_near}}
  stance_shoulder: {{near: shoulder_near, far: shoulder_far}}
  swing_shoulder:  {{near: shoulder_far,  far: shoulder_near}}
poses:
  stand:
    description: both feet down, pelvis upright, shanks a little forward
    joints: {{waist: {{world: 0}}, neck: 0,
             hip_near: {{world: 0, hold: parent}}, knee_near: -5,
             ankle_near: {{world: -2, hold: parent}},
             hip_far: {{world: 0, hold: parent}}, knee_far: -5,
             ankle_far: {{world: -2, hold: parent}},
             shoulder_near: -6, elbow_near: 12, shoulder_far: 6, elbow_far: 12}}
    damping: {{hip_near: 50, knee_near: 50, ankle_near: 30, hip_far: 50, knee_far: 50,
              ankle_far: 30}}
  stride:
    description: the stance leg nearly straight under an upright trunk, the swing leg light, its toes up
    joints: {{waist: {{world: {g('WAIST')}}}, stance_hip: {{world: 0, hold: parent}}, stance_knee: {g('SK')},
             stance_ankle: {g('SA0')}, swing_ankle: {{world: {g('SA_L')}}}}}
    stiffness: {{stance_hip: {g('SHK')}, stance_knee: 1000, stance_ankle: {g('SA_K')}, swing_hip: {g('SWK')},
                swing_knee: {g('SWKK')}, swing_ankle: 800}}
    damping: {{stance_hip: {g('SHD')}, stance_knee: 50, stance_ankle: 30,
              swing_hip: {g('SWING_D')}, swing_knee: {g('SWING_D')}, swing_ankle: 3}}
    max_torque: {{stance_hip: {g('HIPT')}, swing_hip: {g('SWT')}}}
  reach:
    description: the swing knee straightens, the heel first
    joints: {{swing_knee: {g('RK')}, swing_ankle: {{world: {g('SA_R')}}}}}
  land:
    description: "both feet down: the front leg stands, the back foot pushes off on its toes"
    joints: {{waist: {{world: {g('WAIST')}}}, stance_hip: {{world: 0, hold: parent}}, stance_knee: {g('TSK')},
             stance_ankle: {g('SA0')}, swing_hip: {{world: {g('TH')}}}, swing_knee: {g('TKN')}, swing_ankle: {g('TA')}}}
    stiffness: {{stance_hip: {g('SHK')}, stance_knee: 1000, stance_ankle: {g('SA_K')}, swing_hip: {g('TK')},
                swing_knee: {g('TK')}, swing_ankle: {g('TAK')}}}
    max_torque: {{stance_hip: {g('HIPT')}, swing_hip: {g('SWT')}}}
    damping: {{stance_hip: {g('SHD')}, stance_knee: 50, stance_ankle: 30,
              swing_hip: 20, swing_knee: 20, swing_ankle: 10}}
modes:
  standing: []
  stepping:
    - {{input: mouse.x, joint: swing_hip, from: [0, 1], to: [{lh0}, {lh1}], frame: world,
       description: "mouse x: the swing thigh lifts less .. more (in the world)"}}
    - {{input: mouse.y, joint: swing_knee, from: [0, 1], to: [{lk0}, {lk1}],
       description: "mouse y: the swing knee lower .. higher"}}
{lean(ll0, ll1)}{fb(p['CD_L'], p['CV_L'])}{spd}{arms}  reaching:
    - {{input: mouse.x, joint: swing_hip, from: [0, 1], to: [{rh0}, {rh1}], frame: world,
       description: "mouse x: the swing foot lands nearer .. further"}}
{lean(le0, le1)}{fb(p['CD_R'], p['CV_R'])}{spd}{arms}  landing:
{lean(le0, le1)}{ank}{arms}
# Arms from a performer (interfaces/biped-mocap.yaml has the whole figure): A makes
# the arms follow the mocap channels (puppet play biped-walk --mocap CLIP), the legs
# staying on the mouse and space; the arm swing maps above still add to them.
tracking:
  mapping: cmu-131
  joints: [shoulder_near, elbow_near, shoulder_far, elbow_far]
keys:
  - {{key: a, track: angles, description: "arms from a performer (needs --mocap CLIP)"}}
  - {{key: shift+a, track: "off", description: arms back to the walk's own}}
initial: standing
states:
  standing:
    enter: {{pose: stand, mode: standing}}
    keys:
      - {{key: space, goto: lift_near, description: "start: stand on the near leg, the far leg steps"}}
"""
    for X, Y in (("near", "far"), ("far", "near")):
        y += f"""  lift_{X}:
    description: the swing leg lifts to the mouse's place (space now is kept for the next step)
    roles: {X}
    enter: {{pose: stride, mode: stepping}}
    transitions:
      - {{to: reach_{X}, after: {g('LIFT_T')}}}
  reach_{X}:
    description: the swing leg reaches down by itself
    roles: {X}
    enter: {{pose: reach, mode: reaching}}
    transitions:
      - {{to: land_{Y}, when: {{sensor: contact.swing_foot, is: true}}, after: {g('TOUCH')}}}
  land_{Y}:
    description: the foot is down and stands; the back foot pushes off
    roles: {Y}
    enter: {{pose: land, mode: landing}}
    transitions:
      - {{to: ready_{Y}, after: {g('TOE_T')}}}
  ready_{Y}:
    description: both feet down, waiting for space
    roles: {Y}
    keys:
      - {{key: space, goto: lift_{Y}, buffer: {g('BUF')}, description: "step: the back leg lifts"}}
"""
    return y

if __name__ == "__main__":
    p = ast.literal_eval(open(sys.argv[1]).read())
    print(walk(p, sys.argv[2]), end="")
