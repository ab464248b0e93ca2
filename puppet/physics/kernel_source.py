"""The compiled kernel's C text (``physics.kernel`` builds it): KD tracking's pull
loop and forward kinematics, the joint targets it writes, the centre of mass, frame
targets, the support polygon's extent, the two-link IK and a reach's aim and writes
(``pk_reach_aim``, ``pk_reach_set``).

Every line is the Python it replaces, operation for operation, so both give the same
bits: the same sums in the same order and grouping (``a + b * c - d * e`` is
``(a + b * c) - d * e``), no contraction into fused multiply-adds and no
reassociation (compiled with ``-O2 -ffp-contract=off``, never ``-ffast-math``),
doubles in SSE registers (x86-64), libm's ``sin``/``cos`` as Python's ``math`` calls
them (``-fno-builtin``: no ``sincos`` merged from the two), ``math.radians`` as
CPython's ``x * (pi / 180)`` and ``round`` as round-half-even (``nearbyint``).
Chipmunk is called through pymunk's own functions, handed over as pointers
(``pk_init``): the kernel links to nothing but libm.
"""

from puppet.physics.kernel_control import CDEF_CONTROL, SOURCE_CONTROL, TYPES_CONTROL

TYPES = """
typedef struct {
    int n;            /* joints, parents before children (kinematics.joint_order) */
    int *parent, *child;  /* link indices into the poses */
    int *value;       /* index into the values, or -1: not tracked (the joint at 0) */
    int *limited;
    double *ax, *ay, *lo, *hi;
} pk_chain;

typedef struct {
    pk_chain *chain;
    int root;         /* the root link's index */
    double hinge_x, hinge_y;
    int rows;         /* the pulled links (kd_pull.link_plan's rows) */
    int *link;        /* row -> link index */
    int *sole;
    void **body;      /* row -> cpBody * */
    double *m, *gx, *gy, *ks, *ds, *m_T;
    int n_points[2];  /* lowest points: [0] the feet's, [1] every link's */
    int *point_link[2];
    double *px[2], *py[2], *pr[2];
    int n_targets;    /* joint targets written: tracked joints */
    int *target_value, *target_limited;
    double *target_lo, *target_hi;
    void **spring;    /* tracked joint -> cpConstraint * (its damped rotary spring) */
    double *poses;    /* per link: x, y, angle, cos, sin */
    double *targets;  /* per row: x, y, angle */
    int has_prev;
    double *prev; int *prev_has;   /* per row: x, y, angle; 0, 2 or 3 of them */
    double *vel; int *vel_has;
    double *spin; int *spin_has;
} pk_track;

""" + TYPES_CONTROL

CDEF = TYPES + """
void pk_init(void **fns);
void pk_pose(pk_chain *c, const double *vals, const char *has, int root, double ox,
             double oy, double angle, double cs, double sn, double *poses);
void pk_targets(pk_track *t, const double *vals, const char *has, const char *own);
void pk_track_pose(pk_track *t, const double *vals, const char *has, double x, double y,
                   double a, double x0, int lift, double ground, double extra, int vel,
                   double h);
void pk_track_pull(pk_track *t, double weight, const char *own, int stepping, double sx,
                   double sy, int getting_up, int no_lift, double rise, double T);
void pk_com(void **bodies, const double *mass, const double *gx, const double *gy, int n,
            double total, double *out);
double pk_com_spin(void **bodies, const double *mass, const double *gx, const double *gy,
                   int n, double total, double *out);
void pk_frame(void *parent, void *child, void *ref, double angle, int hold_parent,
              void *spring);
int pk_support(void **bodies, int n, double *out);
void pk_two_link(const double *p, double d0, double d1, double dist, double prefer_q2,
                 double *out);
""" + CDEF_CONTROL

SOURCE = TYPES + r"""
#include <math.h>

typedef struct { double x, y; } pk_vect;  /* cpVect */
typedef pk_vect (*pk_getv)(void *);
typedef double (*pk_getd)(void *);
typedef void (*pk_setv)(void *, pk_vect);
typedef void (*pk_setd)(void *, double);

static pk_getv get_position, get_velocity;
static pk_getd get_angle, get_spin, get_moment;
static pk_setv set_velocity;
static pk_setd set_spin, set_rest_angle;
static pk_getd get_rest_angle;
typedef pk_vect (*pk_to_world)(void *, pk_vect);
static pk_to_world to_world;
static pk_getv get_cog;
/* cpContactPointSet (Chipmunk's CP_MAX_CONTACTS_PER_ARBITER is 2) */
typedef struct { pk_vect a, b; double distance; } pk_point;
typedef struct { int count; pk_vect normal; pk_point points[2]; } pk_point_set;
typedef void (*pk_arbiter_fn)(void *, void *, void *);
static void (*each_arbiter)(void *, pk_arbiter_fn, void *);
static pk_point_set (*get_point_set)(void *);

/* CPython's math.radians: x * degToRad, degToRad = Py_MATH_PI / 180.0 */
static const double DEG = 3.14159265358979323846264338327950288 / 180.0;
static const double TURN = 2.0 * 3.14159265358979323846264338327950288;  /* 2 * math.pi */

void pk_init(void **fns)
{
    get_position = (pk_getv)fns[0]; get_angle = (pk_getd)fns[1];
    get_velocity = (pk_getv)fns[2]; get_spin = (pk_getd)fns[3];
    get_moment = (pk_getd)fns[4]; set_velocity = (pk_setv)fns[5];
    set_spin = (pk_setd)fns[6]; set_rest_angle = (pk_setd)fns[7];
    each_arbiter = (void (*)(void *, pk_arbiter_fn, void *))fns[8];
    get_point_set = (pk_point_set (*)(void *))fns[9];
    get_rest_angle = (pk_getd)fns[10]; to_world = (pk_to_world)fns[11];
    get_cog = (pk_getv)fns[12];
}

/* kd_pull.channel_pose */
void pk_pose(pk_chain *c, const double *vals, const char *has, int root, double ox,
             double oy, double angle, double cs, double sn, double *poses)
{
    double *r = poses + 5 * root;
    r[0] = ox; r[1] = oy; r[2] = angle; r[3] = cs; r[4] = sn;
    for (int j = 0; j < c->n; j++) {
        const double *p = poses + 5 * c->parent[j];
        double px = p[0], py = p[1], pa = p[2], co = p[3], si = p[4];
        double ax = c->ax[j], ay = c->ay[j];
        double wx = px + co * ax - si * ay, wy = py + si * ax + co * ay;
        int i = c->value[j];
        double a;
        if (i >= 0 && (has == 0 || has[i])) {
            double v = vals[i] * DEG;
            if (c->limited[j])
                v = v < c->lo[j] ? c->lo[j] : v > c->hi[j] ? c->hi[j] : v;
            a = pa + v;
        } else {
            a = pa + 0.0;
        }
        co = cos(a);
        si = sin(a);
        double *q = poses + 5 * c->child[j];
        q[0] = wx - (co * ax - si * ay); q[1] = wy - (si * ax + co * ay);
        q[2] = a; q[3] = co; q[4] = si;
    }
}

/* Tracker._write_targets without a blend: each tracked joint the tracker owns */
void pk_targets(pk_track *t, const double *vals, const char *has, const char *own)
{
    for (int j = 0; j < t->n_targets; j++) {
        int i = t->target_value[j];
        if ((has != 0 && !has[i]) || (own != 0 && !own[j]))
            continue;
        double target = vals[i] * DEG;
        if (t->target_limited[j])
            target = target < t->target_lo[j] ? t->target_lo[j]
                   : target > t->target_hi[j] ? t->target_hi[j] : target;
        set_rest_angle(t->spring[j], target);
    }
}

/* Tracker._pull up to the loop: the performed pose, its lift, the targets and the
   performed velocities (vel: 0 kept, 1 from the last sample h s ago, 2 none) */
void pk_track_pose(pk_track *t, const double *vals, const char *has, double x, double y,
                   double a, double x0, int lift, double ground, double extra, int vel,
                   double h)
{
    double angle = a * DEG;
    double cs = cos(angle), sn = sin(angle);
    double hx = x0 + x, hy = y;
    double ox = hx - (cs * t->hinge_x - sn * t->hinge_y);
    double oy = hy - (sn * t->hinge_x + cs * t->hinge_y);
    double *P = t->poses;
    pk_pose(t->chain, vals, has, t->root, ox, oy, angle, cs, sn, P);
    double up = 0.0;
    if (lift) {  /* Tracker._lift */
        int k = lift - 1;
        double lowest = INFINITY;
        for (int i = 0; i < t->n_points[k]; i++) {
            const double *p = P + 5 * t->point_link[k][i];
            double yy = p[1] + p[4] * t->px[k][i] + p[3] * t->py[k][i] - t->pr[k][i];
            if (yy < lowest)
                lowest = yy;
        }
        up = ground + extra - lowest;
    }
    double *T = t->targets;
    for (int r = 0; r < t->rows; r++) {
        const double *p = P + 5 * t->link[r];
        double gx = t->gx[r], gy = t->gy[r];
        T[3 * r] = p[0] + p[3] * gx - p[4] * gy;
        T[3 * r + 1] = p[1] + p[4] * gx + p[3] * gy + up;
        T[3 * r + 2] = p[2];
    }
    if (vel == 0)
        return;
    for (int r = 0; r < t->rows; r++) {
        if (vel == 1 && t->prev_has[r]) {
            t->vel[2 * r] = (T[3 * r] - t->prev[3 * r]) / h;
            t->vel[2 * r + 1] = (T[3 * r + 1] - t->prev[3 * r + 1]) / h;
            t->vel_has[r] = 1;
        } else {
            t->vel_has[r] = 0;
        }
        if (vel == 1 && t->sole[r] && t->prev_has[r] > 2) {
            t->spin[r] = (T[3 * r + 2] - t->prev[3 * r + 2]) / h;
            t->spin_has[r] = 1;
        } else {
            t->spin_has[r] = 0;
        }
    }
    for (int r = 0; r < t->rows; r++) {
        t->prev[3 * r] = T[3 * r];
        t->prev[3 * r + 1] = T[3 * r + 1];
        t->prev[3 * r + 2] = T[3 * r + 2];
        t->prev_has[r] = t->sole[r] ? 3 : 2;
    }
    t->has_prev = 1;
}

/* Tracker._pull's loop: each pulled link's velocity change (and a foot's turn) */
void pk_track_pull(pk_track *t, double weight, const char *own, int stepping, double sx,
                   double sy, int getting_up, int no_lift, double rise, double T)
{
    for (int r = 0; r < t->rows; r++) {
        if (own != 0 && !own[r])
            continue;
        double px = t->targets[3 * r], py = t->targets[3 * r + 1];
        double w = weight;
        if (r == stepping) {
            px = sx;
            py = sy;
            w = 1.0;
        }
        double k = t->ks[r] * w, d = t->ds[r] * w;
        if (k == 0.0 && d == 0.0)
            continue;
        double tvx = 0.0, tvy = 0.0;
        if (t->vel_has[r]) {
            tvx = t->vel[2 * r];
            tvy = t->vel[2 * r + 1];
        }
        void *b = t->body[r];
        pk_vect pos = get_position(b);
        double ba = get_angle(b);
        pk_vect v = get_velocity(b);
        double spin = get_spin(b);
        double m = t->m[r], gx = t->gx[r], gy = t->gy[r];
        double cb = cos(ba), sb = sin(ba);
        double wx = cb * gx + -sb * gy + pos.x, wy = sb * gx + cb * gy + pos.y;
        double den = t->m_T[r] + k * T + d;
        double new_vy = (m * v.y / T + k * (py - wy) + d * tvy) / den;
        if (getting_up && new_vy > v.y) {
            if (no_lift) {
                new_vy = v.y;
            } else {
                double top = rise > v.y ? rise : v.y;  /* max(vy, rise) */
                new_vy = top < new_vy ? top : new_vy;  /* min(new_vy, top) */
            }
        }
        pk_vect nv;
        nv.x = (m * v.x / T + k * (px - wx) + d * tvx) / den;
        nv.y = new_vy;
        set_velocity(b, nv);
        if (t->sole[r]) {
            double inertia = get_moment(b);
            double kt = k * inertia / m, dt_ = d * inertia / m;
            double want = t->targets[3 * r + 2];
            double turn = want - ba;
            double n = nearbyint(turn / TURN);
            if (n == 0.0)
                n = 0.0;  /* round() gives the int 0: no -0.0 */
            turn -= TURN * n;
            double spins = t->spin_has[r] ? t->spin[r] : 0.0;
            set_spin(b, (inertia * spin / T + kt * turn + dt_ * spins)
                        / (inertia / T + kt * T + dt_));
        }
    }
}

/* Character._com and _com_velocity: the same sums over the links, in their order */
void pk_com(void **bodies, const double *mass, const double *gx, const double *gy, int n,
            double total, double *out)
{
    double sx = 0.0, sy = 0.0, vx = 0.0, vy = 0.0;
    for (int i = 0; i < n; i++) {
        void *b = bodies[i];
        pk_vect p = get_position(b);
        double a = get_angle(b);
        double c = cos(a), s = sin(a);
        sx += mass[i] * (c * gx[i] + -s * gy[i] + p.x);
        sy += mass[i] * (s * gx[i] + c * gy[i] + p.y);
        pk_vect v = get_velocity(b);
        vx += mass[i] * v.x;
        vy += mass[i] * v.y;
    }
    out[0] = sx / total; out[1] = sy / total;
    out[2] = vx / total; out[3] = vy / total;
}

/* Character._com_spin: the links' angular momentum about the centre of mass (com: its
   x, y, vx, vy, as pk_com gives them) over their moment of inertia there, in the same
   sums (Python's ``a += b + c`` is ``a + (b + c)``) */
static double pk_spin_about(void **bodies, const double *mass, const double *gx,
                            const double *gy, int n, const double *com)
{
    double cx = com[0], cy = com[1], vx = com[2], vy = com[3];
    double momentum = 0.0, inertia = 0.0;
    for (int i = 0; i < n; i++) {
        void *b = bodies[i];
        pk_vect p = get_position(b);
        double a = get_angle(b);
        double c = cos(a), s = sin(a);
        double rx = c * gx[i] - s * gy[i] + p.x - cx;
        double ry = s * gx[i] + c * gy[i] + p.y - cy;
        double moment = get_moment(b);
        pk_vect v = get_velocity(b);
        double w = get_spin(b);
        momentum += mass[i] * (rx * (v.y - vy) - ry * (v.x - vx)) + moment * w;
        inertia += moment + mass[i] * (rx * rx + ry * ry);
    }
    return momentum / inertia;
}

/* the centre of mass into out (pk_com), and the body's spin about it */
double pk_com_spin(void **bodies, const double *mass, const double *gx, const double *gy,
                   int n, double total, double *out)
{
    pk_com(bodies, mass, gx, gy, n, total, out);
    return pk_spin_about(bodies, mass, gx, gy, n, out);
}

/* FrameTargets._solve (interface/controllers/frame.py): the joint's target that puts
   its child link (or, hold_parent, its parent) at ``angle`` in the world or relative
   to ``ref`` (NULL: the world), in the turn the joint is in now. libm's remainder is
   IEEE's, exact, so it is math.remainder's to the bit. */
void pk_frame(void *parent, void *child, void *ref, double angle, int hold_parent,
              void *spring)
{
    double p = get_angle(parent);
    double c = get_angle(child);
    double want = angle + (ref ? get_angle(ref) : 0.0);
    double q = hold_parent ? c - want : want - p;
    double now = c - p;
    set_rest_angle(spring, now + remainder(q - now, TURN));
}

/* Character.support_extent: the leftmost and rightmost x of the contact points of the
   bodies' arbiters (cpBodyEachArbiter, cpArbiterGetContactPointSet's pointA.x, in
   Chipmunk's order), compared as Python's min and max do (a later point replaces
   only a smaller, resp. larger one); returns how many points there were */
typedef struct { int n; double lo, hi; } pk_extent;

static void pk_extent_of(void *body, void *arbiter, void *data)
{
    pk_extent *e = (pk_extent *)data;
    pk_point_set got = get_point_set(arbiter);
    (void)body;
    for (int i = 0; i < got.count; i++) {
        double x = got.points[i].a.x;
        if (e->n == 0) {
            e->lo = x; e->hi = x;
        } else {
            if (x < e->lo) e->lo = x;
            if (x > e->hi) e->hi = x;
        }
        e->n++;
    }
}

int pk_support(void **bodies, int n, double *out)
{
    pk_extent e = {0, 0.0, 0.0};
    for (int i = 0; i < n; i++)
        each_arbiter(bodies[i], pk_extent_of, &e);
    out[0] = e.lo; out[1] = e.hi;
    return e.n;
}

/* interface/ik_two.py: TwoLink.dls and TwoLink.solve, operation for operation. p holds
   l1, l2, p1, p2, l1sq, l2sq, den, ax0, ay0, ax1, ay1, has0, lo0, hi0, has1, lo1, hi1,
   lam2, tol2, iterations (has: the joint has limits); ``dist`` is math.hypot(d0, d1),
   worked out by CPython (its own algorithm, not libm's hypot) */
static void pk_dls(const double *p, double d0, double d1, double q0, double q1,
                   double *out)
{
    double ax0 = p[7], ay0 = p[8], ax1 = p[9], ay1 = p[10];
    int has0 = p[11] != 0.0, has1 = p[14] != 0.0;
    double lo0 = p[12], hi0 = p[13], lo1 = p[15], hi1 = p[16];
    double lam2 = p[17], tol2 = p[18];
    int iterations = (int)p[19];
    double angle = 0.0 + q0;
    double c = cos(angle), s = sin(angle);
    double jx = 0.0 + (c * ax0 - s * ay0);
    double jy = 0.0 + (s * ax0 + c * ay0);
    angle = angle + q1;
    c = cos(angle); s = sin(angle);
    double ex = jx + (c * ax1 - s * ay1);
    double ey = jy + (s * ax1 + c * ay1);
    double rx = d0 - ex, ry = d1 - ey;
    double err2 = rx * rx + ry * ry;
    for (int it = 0; it < iterations; it++) {
        if (err2 < tol2)
            break;
        double c0x = -ey, c0y = ex, c1x = -(ey - jy), c1y = ex - jx;
        if (has0) {
            double push = c0x * rx + c0y * ry;
            if ((q0 <= lo0 && push < 0) || (q0 >= hi0 && push > 0)) {
                c0x = 0.0; c0y = 0.0;
            }
        }
        if (has1) {
            double push = c1x * rx + c1y * ry;
            if ((q1 <= lo1 && push < 0) || (q1 >= hi1 && push > 0)) {
                c1x = 0.0; c1y = 0.0;
            }
        }
        double a = lam2 + (c0x * c0x + c1x * c1x);
        double b = 0.0 + c0x * c0y + c1x * c1y;
        double cc = lam2 + (c0y * c0y + c1y * c1y);
        double det = a * cc - b * b;
        double w0 = (cc * rx - b * ry) / det, w1 = (a * ry - b * rx) / det;
        double s0 = c0x * w0 + c0y * w1, s1 = c1x * w0 + c1y * w1;
        double scale = 1.0;
        double n0, n1, njx, njy, nx, ny, nrx, nry, new_err2;
        for (;;) {
            n0 = q0 + scale * s0;
            if (has0) {
                double m = n0 > lo0 ? n0 : lo0;
                n0 = m < hi0 ? m : hi0;
            }
            n1 = q1 + scale * s1;
            if (has1) {
                double m = n1 > lo1 ? n1 : lo1;
                n1 = m < hi1 ? m : hi1;
            }
            angle = 0.0 + n0;
            c = cos(angle); s = sin(angle);
            njx = 0.0 + (c * ax0 - s * ay0);
            njy = 0.0 + (s * ax0 + c * ay0);
            angle = angle + n1;
            c = cos(angle); s = sin(angle);
            nx = njx + (c * ax1 - s * ay1);
            ny = njy + (s * ax1 + c * ay1);
            nrx = d0 - nx; nry = d1 - ny;
            new_err2 = nrx * nrx + nry * nry;
            if (new_err2 < err2 || scale < 1e-3)
                break;
            scale *= 0.5;
        }
        if (new_err2 >= err2)
            break;
        double moved = fabs(n0 - q0) + fabs(n1 - q1);
        q0 = n0; q1 = n1; jx = njx; jy = njy;
        ex = nx; ey = ny; rx = nrx; ry = nry; err2 = new_err2;
        if (moved < 1e-9)
            break;
    }
    out[0] = q0; out[1] = q1;
}

/* ik_two.round_clamp: an angle past its limits to the limit nearer round the circle */
static double round_clamp(double q, double clamped, double lo, double hi)
{
    if (q < lo && q + TURN - hi < lo - q) return hi;
    if (q > hi && lo + TURN - q < q - hi) return lo;
    return clamped;
}

void pk_two_link(const double *p, double d0, double d1, double dist, double prefer_q2,
                 double *out)
{
    double l1 = p[0], l2 = p[1], p1 = p[2], p2 = p[3];
    int has0 = p[11] != 0.0, has1 = p[14] != 0.0;
    double c = (dist * dist - p[4] - p[5]) / p[6];
    c = c > -1.0 ? c : -1.0;
    c = c < 1.0 ? c : 1.0;
    double beta = acos(c);
    double q2 = remainder(beta + p1 - p2, TURN);
    double other = -acos(c);
    double q2b = remainder(other + p1 - p2, TURN);
    if (fabs(remainder(q2b - prefer_q2, TURN)) < fabs(remainder(q2 - prefer_q2, TURN))) {
        beta = other; q2 = q2b;
    }
    double q1 = remainder(atan2(d1, d0) - (p1 + atan2(l2 * sin(beta), l1 + l2 * cos(beta))),
                          TURN);
    int same = 1;
    double c1 = q1, c2 = q2;
    if (has0) {
        double m = q1 > p[12] ? q1 : p[12];
        c1 = m < p[13] ? m : p[13];
        same = c1 == q1;
        if (!same) c1 = round_clamp(q1, c1, p[12], p[13]);
    }
    if (has1) {
        double m = q2 > p[15] ? q2 : p[15];
        c2 = m < p[16] ? m : p[16];
        same = same && c2 == q2;
        if (c2 != q2) c2 = round_clamp(q2, c2, p[15], p[16]);
    }
    if (same) {
        out[0] = q1; out[1] = q2;
        return;
    }
    pk_dls(p, d0, d1, c1, c2, out);
}

""" + SOURCE_CONTROL
