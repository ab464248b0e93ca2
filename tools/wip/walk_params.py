"""Parametric walk: lift -> reach -> touchdown -> toeoff (double support, roles swapped)
-> ready (waits for a press, buffered) -> lift."""
DEF = dict(
    LIFT_T=0.2, LH=30.0, LHX=30.0, LK=-60.0, LKY=40.0, CV_L=10.0, CD_L=0.0,
    RH=0.0, RK=-5.0, CD_R=40.0, CV_R=5.0, RHX=10.0,
    SK=-3.0, SA_K=300.0, LEAN=-2.0, LEANX=-6.0, SA_L=0.0, SA_R=5.0, SWING_D=8.0,
    TOE_T=0.08, TSK=-4.0, TKN=-25.0, TA=-15.0, TH=-15.0, TK=200.0, TAK=600.0,
    ANK_D=-60.0, ANK_V=-10.0, ANK_D0=0.0, TOUCH=0.017, BUF=1.0, PUSH_DX=0.08, PUSH_A=-18.0,
    HIPT=250.0, KNEET=335.0, ANKT=227.0, ARM=1.0, SWK=300.0, SWKK=300.0, LEAN_L=0.0, SA0=0.0, WAIST=0.0, SV0=0.7, SVK=0.0, SHK=1000.0, SHD=50.0, SWT=400.0,
)
ROLES = """roles:
  stance_hip:      {near: hip_near,      far: hip_far}
  stance_knee:     {near: knee_near,     far: knee_far}
  stance_ankle:    {near: ankle_near,    far: ankle_far}
  swing_hip:       {near: hip_far,       far: hip_near}
  swing_knee:      {near: knee_far,      far: knee_near}
  swing_ankle:     {near: ankle_far,     far: ankle_near}
  stance_foot:     {near: foot_near,     far: foot_far}
  swing_foot:      {near: foot_far,      far: foot_near}
  swing_thigh:     {near: thigh_far,     far: thigh_near}
  stance_shoulder: {near: shoulder_near, far: shoulder_far}
  swing_shoulder:  {near: shoulder_far,  far: shoulder_near}
"""
def r(v):
    return round(v, 3) if isinstance(v, float) else v

def gen(**kw):
    p = dict(DEF); p.update(kw)
    g = lambda k: r(p[k])
    arms = f"""    - {{input: sensor.angle.swing_thigh, joint: stance_shoulder, from: [0, 1],
       to: [0, {g('ARM')}], clamp: false, combine: add}}
    - {{input: sensor.angle.swing_thigh, joint: swing_shoulder, from: [0, 1],
       to: [0, {r(-p['ARM'])}], clamp: false, combine: add}}
"""
    lean = f"""    - {{input: mouse.x, joint: stance_hip, from: [0, 1], to: [{r(p['LEAN'] - p['LEANX']/2)}, {r(p['LEAN'] + p['LEANX']/2)}], frame: world,
       hold: parent}}
"""
    lean_l = f"""    - {{input: mouse.x, joint: stance_hip, from: [0, 1], to: [{r(p['LEAN'] + p['LEAN_L'] - p['LEANX']/2)}, {r(p['LEAN'] + p['LEAN_L'] + p['LEANX']/2)}], frame: world,
       hold: parent}}
"""
    fb = lambda cd, cv: f"""    - {{input: sensor.com.dx.stance_foot, joint: swing_hip, from: [0, 1], to: [0, {r(cd)}],
       clamp: false, combine: add}}
    - {{input: sensor.com.vx, joint: swing_hip, from: [0, 1], to: [0, {r(cv)}], clamp: false,
       combine: add}}
"""
    spd = f"""    - {{input: sensor.com.vx, joint: stance_ankle, from: [{g('SV0')}, {r(p['SV0'] + 1)}], to: [0, {r(-p['SVK'])}], clamp: false,
       combine: add}}
""" if p['SVK'] else ""
    ank = f"""    - {{input: sensor.com.dx.stance_foot, joint: stance_ankle, from: [{g('ANK_D0')}, {r(p['ANK_D0'] + 1)}], to: [0, {g('ANK_D')}],
       clamp: false, combine: add}}
    - {{input: sensor.com.vx, joint: stance_ankle, from: [0, 1], to: [0, {g('ANK_V')}], clamp: false,
       combine: add}}
"""
    y = f"""name: biped-walk
description: experimental
character: biped
scene: biped-track
slowdown: 3
control_rate: 120
gains:
  ankle_near: {{max_torque: {g('ANKT')}}}
  ankle_far: {{max_torque: {g('ANKT')}}}
  knee_near: {{max_torque: {g('KNEET')}}}
  knee_far: {{max_torque: {g('KNEET')}}}
  hip_near: {{max_torque: {g('HIPT')}}}
  hip_far: {{max_torque: {g('HIPT')}}}
{ROLES}poses:
  stand:
    joints: {{waist: {{world: 0}}, neck: 0,
             hip_near: {{world: 0, hold: parent}}, knee_near: -5,
             ankle_near: {{world: -2, hold: parent}},
             hip_far: {{world: 0, hold: parent}}, knee_far: -5,
             ankle_far: {{world: -2, hold: parent}},
             shoulder_near: -6, elbow_near: 12, shoulder_far: 6, elbow_far: 12}}
  stride:
    joints: {{waist: {{world: {g('WAIST')}}}, stance_hip: {{world: 0, hold: parent}}, stance_knee: {g('SK')},
             stance_ankle: {g('SA0')}, swing_ankle: {{world: {g('SA_L')}}}}}
    stiffness: {{stance_hip: 1000, stance_ankle: {g('SA_K')}, stance_knee: 1000, swing_hip: {g('SWK')}, swing_knee: {g('SWKK')}, swing_ankle: 800}}
    damping: {{stance_hip: 50, stance_knee: 50, stance_ankle: 30,
              swing_hip: {g('SWING_D')}, swing_knee: {g('SWING_D')}, swing_ankle: 3}}
  reach:
    joints: {{swing_knee: {g('RK')}, swing_ankle: {{world: {g('SA_R')}}}}}
  push:
    joints: {{stance_ankle: {g('PUSH_A')}, stance_knee: -1}}
  toeoff:
    joints: {{waist: {{world: {g('WAIST')}}}, stance_hip: {{world: 0, hold: parent}}, stance_knee: {g('TSK')},
             stance_ankle: {g('SA0')}, swing_knee: {g('TKN')}, swing_ankle: {g('TA')}, swing_hip: {{world: {g('TH')}}}}}
    stiffness: {{stance_hip: 1000, stance_ankle: {g('SA_K')}, stance_knee: 1000, swing_hip: {g('TK')}, swing_knee: {g('TK')}, swing_ankle: {g('TAK')}}}
    damping: {{stance_hip: 50, stance_knee: 50, stance_ankle: 30,
              swing_hip: 20, swing_knee: 20, swing_ankle: 10}}
modes:
  standing: []
  stepping:
    - {{input: mouse.x, joint: swing_hip, from: [0, 1], to: [{r(p['LH'] - p['LHX']/2)}, {r(p['LH'] + p['LHX']/2)}], frame: world}}
    - {{input: mouse.y, joint: swing_knee, from: [0, 1], to: [{r(p['LK'] + p['LKY']/2)}, {r(p['LK'] - p['LKY']/2)}]}}
{lean_l}{fb(p['CD_L'], p['CV_L'])}{spd}{arms}  reaching:
    - {{input: mouse.x, joint: swing_hip, from: [0, 1], to: [{r(p['RH'] - p['RHX']/2)}, {r(p['RH'] + p['RHX']/2)}], frame: world}}
{lean}{fb(p['CD_R'], p['CV_R'])}{spd}{arms}  planted:
{lean}{ank}{arms}"""
    y += """initial: standing
states:
  standing:
    enter: {pose: stand, mode: standing}
    keys:
      - {key: space, goto: lift_near}
"""
    for X, Y in (("near", "far"), ("far", "near")):
        y += f"""  lift_{X}:
    roles: {X}
    enter: {{pose: stride, mode: stepping}}
    transitions:
      - {{to: reach_{X}, after: {g('LIFT_T')}}}
  reach_{X}:
    roles: {X}
    enter: {{pose: reach, mode: reaching}}
    transitions:
      - {{to: push_{X}, when: {{sensor: com.dx.stance_foot, above: {g('PUSH_DX')}}}}}
      - {{to: toeoff_{Y}, when: {{sensor: contact.swing_foot, is: true}}, after: {g('TOUCH')}}}
  push_{X}:
    roles: {X}
    enter: {{pose: push}}
    transitions:
      - {{to: toeoff_{Y}, when: {{sensor: contact.swing_foot, is: true}}, after: {g('TOUCH')}}}
  toeoff_{Y}:
    roles: {Y}
    enter: {{pose: toeoff, mode: planted}}
    transitions:
      - {{to: ready_{Y}, after: {g('TOE_T')}}}
  ready_{Y}:
    roles: {Y}
    keys:
      - {{key: space, goto: lift_{Y}, buffer: {g('BUF')}}}
"""
    return y
