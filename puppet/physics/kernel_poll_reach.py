"""The C of running reaches and armed grasps for ``pk_poll``'s tick (``kernel_poll``;
the Python it mirrors operation for operation: ``ReachController.tick``,
``GraspController.tick``, ``props._outside``): CPython 3.11's ``math.hypot`` to the bit,
a segment's nearest outside point, a grasp's catch test and the reaches' aim and writes.
Kept apart from the loop because it is one idea, the reaching hand's; it reads
``pk_poll_plan`` (``POLL_TYPES``).
"""

REACH_SOURCE = r"""
/* CPython 3.11's math.hypot of two finite or not numbers (mathmodule.c's
   vector_norm, with its double-length helpers): not libm's, so the bits are Python's */
typedef struct { double hi, lo; } pk_dl;

static pk_dl pk_dl_split(double x)
{
    double t = x * 134217729.0;
    double hi = t - (t - x);
    pk_dl r = {hi, x - hi};
    return r;
}

static pk_dl pk_dl_mul(double x, double y)
{
    pk_dl xx = pk_dl_split(x), yy = pk_dl_split(y);
    double p = xx.hi * yy.hi;
    double q = xx.hi * yy.lo + xx.lo * yy.hi;
    double z = p + q;
    pk_dl r = {z, p - z + q + xx.lo * yy.lo};
    return r;
}

static pk_dl pk_dl_fast_sum(double a, double b)
{
    double x = a + b;
    double z = x - a;
    pk_dl r = {x, b - z};
    return r;
}

static double pk_norm(int n, double *vec, double max, int found_nan)
{
    double x, h, scale, csum = 1.0, frac1 = 0.0, frac2 = 0.0;
    pk_dl pr, sm;
    int max_e;
    if (isinf(max))
        return max;
    if (found_nan)
        return NAN;
    if (max == 0.0 || n <= 1)
        return max;
    frexp(max, &max_e);
    if (max_e < -1023) {
        for (int i = 0; i < n; i++)
            vec[i] /= DBL_MIN;
        return DBL_MIN * pk_norm(n, vec, max / DBL_MIN, found_nan);
    }
    scale = ldexp(1.0, -max_e);
    for (int i = 0; i < n; i++) {
        x = vec[i];
        x *= scale;
        pr = pk_dl_mul(x, x);
        sm = pk_dl_fast_sum(csum, pr.hi);
        csum = sm.hi;
        frac1 += pr.lo;
        frac2 += sm.lo;
    }
    h = sqrt(csum - 1.0 + (frac1 + frac2));
    pr = pk_dl_mul(-h, h);
    sm = pk_dl_fast_sum(csum, pr.hi);
    csum = sm.hi;
    frac1 += pr.lo;
    frac2 += sm.lo;
    x = csum - 1.0 + (frac1 + frac2);
    h += x / (2.0 * h);
    return h / scale;
}

double pk_hypot(double a, double b)
{
    double v[2] = {fabs(a), fabs(b)}, max = 0.0;
    int found_nan = 0;
    for (int i = 0; i < 2; i++) {
        found_nan |= isnan(v[i]);
        if (v[i] > max)
            max = v[i];
    }
    return pk_norm(2, v, max, found_nan);
}

/* props._outside: the parameter nearest u of a segment's point at least r from
   (cx, cy); 0 when the whole segment is within r (else 1, *u set) */
static int pk_outside(double *u, double ax, double ay, double vx, double vy, double vv,
                      double cx, double cy, double r)
{
    double dx = ax - cx, dy = ay - cy;
    if (pow(dx + *u * vx, 2.0) + pow(dy + *u * vy, 2.0) >= r * r)
        return 1;
    double b = (dx * vx + dy * vy) / vv;
    double c = (dx * dx + dy * dy - r * r) / vv;
    double m = b * b - c;
    double root = sqrt(m > 0.0 ? m : 0.0);  /* math.sqrt(max(0.0, ...)) */
    double inside[2] = {-b - root, -b + root}, best = 0.0, key = 0.0;
    int found = 0;
    for (int i = 0; i < 2; i++) {
        double t = inside[i];
        if (0.0 <= t && t <= 1.0) {  /* min(allowed, key=abs(s - u)): the first least */
            double k = fabs(t - *u);
            if (!found || k < key) {
                best = t; key = k; found = 1;
            }
        }
    }
    if (found)
        *u = best;
    return found;
}

/* GraspController.tick's test for armed grasp ``j`` (try_grasp: the nearest of its
   places, Prop.nearest's arithmetic, or its world points, within the tolerance): 1
   when one of its places is within it, or nearly (Python's tick then grasps or finds
   it does not). A place surely farther (its squared distance, or its segment's
   ignoring the skipped part, beyond the tolerance by far more than any rounding) is
   not worked out further. */
static int pk_catches(const pk_poll_plan *p, int j)
{
    pk_vect local = {p->a_ex[j], p->a_ey[j]};
    pk_vect e = to_world(p->a_end[j], local);
    double wx = e.x, wy = e.y, r = p->a_tol[j];
    double reach = r * (1.0 + 1e-9) + 1e-12, far = r * (1.0 + 1e-6) + 1e-9;
    double cx = p->a_sx[j], cy = p->a_sy[j];
    int skip = p->a_skip[j];
    far *= far;
    for (int i = p->a_p0[j]; i < p->a_p1[j]; i++) {
        double px = p->a_px[i], py = p->a_py[i];
        double dx = px - wx, dy = py - wy;
        if (dx * dx + dy * dy > far)
            continue;
        if (skip && pk_hypot(px - cx, py - cy) < r)
            continue;
        if (!(pk_hypot(dx, dy) > reach))
            return 1;
    }
    for (int i = p->a_s0[j]; i < p->a_s1[j]; i++) {
        double ax = p->a_sax[i], ay = p->a_say[i], vx = p->a_svx[i], vy = p->a_svy[i];
        double vv = p->a_svv[i];
        double u = ((wx - ax) * vx + (wy - ay) * vy) / vv;
        double m = u > 0.0 ? u : 0.0;
        u = m < 1.0 ? m : 1.0;
        double dx = ax + u * vx - wx, dy = ay + u * vy - wy;
        if (dx * dx + dy * dy > far)  /* (the segment's nearest: the skipped part's
                                          points are no nearer) */
            continue;
        if (skip && !pk_outside(&u, ax, ay, vx, vy, vv, cx, cy, r))
            continue;
        if (!(pk_hypot(ax + u * vx - wx, ay + u * vy - wy) > reach))
            return 1;
    }
    return 0;
}

/* The running reaches at ``s`` (ReachController.tick's fast path): each one's aim;
   1 when one would grasp (its end within its tolerance of the goal: try_grasp's
   test, met or nearly) or there is no kernel's hypot to trust (then Python's tick at
   ``s`` does it all, nothing written here); else each one's solve and writes, in
   the reaches' order */
static int pk_reaches(pk_poll_plan *p, int s)
{
    for (int j = 0; j < p->n_armed; j++)  /* (the armed grasps: Python's, if one holds) */
        if (pk_catches(p, j))
            return 1;
    for (int j = 0; j < p->n_reach; j++) {
        double *out = p->r_out + 4 * j;
        pk_reach_aim((double)(s - p->r_start[j]), p->r_parent[j], p->r_ax[j], p->r_ay[j],
                     p->r_goal[j], p->r_gx[j], p->r_gy[j], p->r_p0x[j], p->r_p0y[j],
                     p->r_steps[j], out);
        if (p->r_end[j]) {  /* try_grasp: hypot(end - goal) <= tolerance, with a margin */
            pk_vect local = {p->r_ex[j], p->r_ey[j]};
            pk_vect e = to_world(p->r_end[j], local);
            double d = pk_hypot(e.x - out[2], e.y - out[3]);
            if (!(d > p->r_tol[j] * (1.0 + 1e-9) + 1e-12))
                return 1;
        }
    }
    for (int j = 0; j < p->n_reach; j++) {
        double *out = p->r_out + 4 * j;
        pk_reach_set(p->r_params[j], out[0], out[1], pk_hypot(out[0], out[1]),
                     p->r_spring0[j], p->r_spring1[j], p->r_own1[j], p->r_q);
    }
    return 0;
}

"""
