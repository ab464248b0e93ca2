"""The compiled kernel's C for whole controllers' ticks (``kernel_source`` appends it):
a reach's aim and writes (``pk_reach_aim``, ``pk_reach_set``: ``ReachController.tick``
for a two-link chain) and feedback's add maps with their sensors (``pk_feedback_tick``:
``Feedback.tick``, see ``interface.controllers.feedback_kernel``). Written, like the
rest, operation for operation as the Python it replaces (kernel_source's docstring),
with the Chipmunk calls and helpers of kernel_source's part (``to_world``,
``get_rest_angle``, ``get_cog``, ``pk_com``, ``pk_support``, ``pk_two_link``).
"""

TYPES_CONTROL = """
typedef struct {
    int n_bodies;     /* the centre of mass's links (pk_com's arguments) */
    void **bodies;
    double *mass, *gx, *gy;
    double total;
    int n_sensors;    /* each sensor: its kind (PK_S_*), link(s), value (file units) */
    int *kind;
    void **a, **b;
    double *values;   /* out; a PK_S_GIVEN's value is put here by the caller */
    int support_given;  /* the PK_S_SUPPORT values too (right after a restore) */
    double gravity;   /* -space.gravity.y, for PK_S_FALL_TIME */
    int n_rows;       /* each add map's joint: sensor (-1: a constant, in gain), line */
    int *sensor, *clamp, *slot;
    double *x0, *inv, *lo, *span, *gain;
    int n_slots;      /* every servo: its spring, and what Feedback keeps of it */
    void **spring;
    double *acc;
    int *added, *order;
    double *base, *last;
    int *has;
    long long *seq;   /* when the joint entered base and last (their dicts' order) */
    long long counter;
} pk_feedback;
"""[1:]  # (the text from its first line)

CDEF_CONTROL = """
int pk_feedback_tick(pk_feedback *f);
void pk_reach_aim(double done, void *parent, double ax, double ay, void *goal_body, double gx,
                  double gy, double p0x, double p0y, double steps, double *out);
void pk_reach_set(const double *p, double d0, double d1, double dist, void *spring0,
                  void *spring1, int own1, double *out);
"""[1:]  # (the text from its first line)

SOURCE_CONTROL = r"""
/* ReachController.tick's aim, for a two-link chain (interface/controllers/reach.py and
   ik.Chain.solve): the goal (``goal_body``'s local point in the world, Prop.point_world;
   NULL: the world point itself), the Hermite-eased point from p0 towards it at
   ``done / steps`` of the way, and that point in the chain's first joint's parent frame
   from its anchor. out: d0, d1, the goal's x, y. (math.hypot(d0, d1) is CPython's own:
   worked out there, then pk_reach_set.) */
void pk_reach_aim(double done, void *parent, double ax, double ay, void *goal_body, double gx,
                  double gy, double p0x, double p0y, double steps, double *out)
{
    if (goal_body) {
        pk_vect local = {gx, gy};
        pk_vect g = to_world(goal_body, local);
        gx = g.x; gy = g.y;
    }
    double u = done / steps;
    double m = u > 0.0 ? u : 0.0;  /* min(1.0, max(0.0, u)) */
    u = m < 1.0 ? m : 1.0;
    double h = u * u * (3.0 - 2.0 * u);
    double px = p0x + h * (gx - p0x), py = p0y + h * (gy - p0y);
    pk_vect anchor = {ax, ay};
    pk_vect base = to_world(parent, anchor);
    double angle = -get_angle(parent);
    double c = cos(angle), s = sin(angle);
    double dx = px - base.x, dy = py - base.y;
    out[0] = c * dx - s * dy;
    out[1] = s * dx + c * dy;
    out[2] = gx; out[3] = gy;
}

/* ... and its solve and writes: pk_two_link preferring spring1's target now, then the
   first joint's target into spring0 (NULL: not owned) and the second's into spring1
   when ``own1`` */
void pk_reach_set(const double *p, double d0, double d1, double dist, void *spring0,
                  void *spring1, int own1, double *out)
{
    pk_two_link(p, d0, d1, dist, get_rest_angle(spring1), out);
    if (spring0)
        set_rest_angle(spring0, out[0]);
    if (own1)
        set_rest_angle(spring1, out[1]);
}

/* The sensors the kernel reads (conditions.reader's), for feedback's maps and the
   stepping loop's conditions (kernel_poll): PK_S_GIVEN is read in Python and handed
   over, PK_S_SUPPORT (the support polygon) is pk_feedback's alone. */
#define PK_S_GIVEN 0
#define PK_S_COM_X 1
#define PK_S_COM_Y 2
#define PK_S_COM_VX 3
#define PK_S_COM_VY 4
#define PK_S_COM_DX 5
#define PK_S_ANGLE 6
#define PK_S_SPIN 7
#define PK_S_JOINT 8
#define PK_S_HEIGHT 9
#define PK_S_LEAD 10
#define PK_S_SUPPORT 11
#define PK_S_FALL_TIME 12
#define PK_S_CONTACT 13
#define PK_S_COM_SPIN 14
#define PK_S_COM(kind) (((kind) >= PK_S_COM_X && (kind) <= PK_S_COM_DX) \
                        || (kind) == PK_S_SUPPORT || (kind) == PK_S_FALL_TIME \
                        || (kind) == PK_S_COM_SPIN)

static pk_vect pk_link_position(void *b)  /* Character.link_position */
{
    return to_world(b, get_cog(b));
}

static void pk_touched(void *body, void *arbiter, void *data)
{
    (void)body; (void)arbiter;
    *(int *)data = 1;
}

/* a sensor's value in its reader's units (radians, rad/s, m, m/s, s; a contact 0 or
   1), on links a and b; com: the centre of mass's x, y, vx, vy (pk_com, for the kinds
   PK_S_COM says), gravity: -space.gravity.y; PK_S_SUPPORT and PK_S_COM_SPIN (the
   links' sums) are read by the callers */
static double pk_sensor(int kind, void *a, void *b, const double *com, double gravity)
{
    int touching;
    double y, vy;
    switch (kind) {
    case PK_S_COM_X: case PK_S_COM_Y: case PK_S_COM_VX: case PK_S_COM_VY:
        return com[kind - PK_S_COM_X];
    case PK_S_COM_DX: return com[0] - pk_link_position(a).x;
    case PK_S_ANGLE: return remainder(get_angle(a), TURN);
    case PK_S_SPIN: return get_spin(a);
    case PK_S_JOINT: return get_angle(a) - get_angle(b);
    case PK_S_HEIGHT: return pk_link_position(a).y;
    case PK_S_LEAD: return pk_link_position(a).x - pk_link_position(b).x;
    case PK_S_FALL_TIME:  /* conditions._fall_time */
        y = com[1];
        if (y <= 0.0)
            return 0.0;
        if (gravity <= 0.0)
            return INFINITY;
        vy = com[3];
        return (vy + sqrt(vy * vy + 2.0 * gravity * y)) / gravity;
    default:  /* PK_S_CONTACT */
        touching = 0;
        each_arbiter(a, pk_touched, &touching);
        return touching ? 1.0 : 0.0;
    }
}

/* Feedback.tick's add maps with their sensors (interface/controllers/feedback.py,
   conditions.map_reader, maps.compile_contribution), for a set of maps without sensor
   maps that set targets: each sensor read (the centre of mass once, as
   Character.sample: ``com``, already read when ``*com_done``; the support polygon as
   Character.support_extent, handed over right after a restore, when it is the
   snapshot's), each map's value added to its joint's sum in file order (the first to
   0.0), a joint no map adds to any more put back to its base if nothing else wrote
   it, then each joint's target its base plus the sum (the base re-read if something
   else wrote the target since). Returns how many joints it adds to. pk_poll runs it
   between Python's ticks with the same struct. */
static int pk_feedback_add(pk_feedback *f, double *com, int *com_done)
{
    static const double TO_DEG = 180.0 / 3.14159265358979323846264338327950288;
    int n = 0;
    for (int i = 0; i < f->n_sensors; i++) {
        int kind = f->kind[i];
        double v;
        if (kind == PK_S_GIVEN || (kind == PK_S_SUPPORT && f->support_given))
            continue;  /* (its value put there by the caller) */
        if (PK_S_COM(kind) && !*com_done) {
            pk_com(f->bodies, f->mass, f->gx, f->gy, f->n_bodies, f->total, com);
            *com_done = 1;
        }
        if (kind == PK_S_SUPPORT) {  /* com.dx.support: from the support polygon's middle */
            double extent[2];
            v = pk_support(f->bodies, f->n_bodies, extent)
                ? com[0] - 0.5 * (extent[0] + extent[1]) : 0.0;
        } else if (kind == PK_S_COM_SPIN) {  /* com.spin, in map_reader's degrees */
            v = pk_spin_about(f->bodies, f->mass, f->gx, f->gy, f->n_bodies, com) * TO_DEG;
        } else {
            v = pk_sensor(kind, f->a[i], f->b[i], com, f->gravity);
            if (kind == PK_S_ANGLE || kind == PK_S_SPIN || kind == PK_S_JOINT)
                v = v * TO_DEG;  /* map_reader's degrees */
        }
        f->values[i] = v;
    }
    for (int r = 0; r < f->n_rows; r++) {
        double value;
        if (f->sensor[r] < 0) {
            value = f->gain[r];
        } else {
            double u = (f->values[f->sensor[r]] - f->x0[r]) * f->inv[r];
            if (f->clamp[r])
                u = u < 0.0 ? 0.0 : u > 1.0 ? 1.0 : u;
            value = f->gain[r] * (f->lo[r] + u * f->span[r]);
        }
        int s = f->slot[r];
        if (f->added[s]) {
            f->acc[s] = f->acc[s] + value;
        } else {
            f->added[s] = 1;
            f->acc[s] = 0.0 + value;
            f->order[n++] = s;
        }
    }
    for (int s = 0; s < f->n_slots; s++) {
        if (f->has[s] && !f->added[s]) {  /* an add map went inactive */
            if (get_rest_angle(f->spring[s]) == f->last[s])
                set_rest_angle(f->spring[s], f->base[s]);
            f->has[s] = 0;
        }
    }
    for (int k = 0; k < n; k++) {
        int s = f->order[k];
        double now = get_rest_angle(f->spring[s]);
        double b = f->has[s] && now == f->last[s] ? f->base[s] : now;  /* rewritten? */
        if (!f->has[s]) {
            f->has[s] = 1;
            f->seq[s] = ++f->counter;
        }
        f->base[s] = b;
        f->last[s] = b + f->acc[s];
        set_rest_angle(f->spring[s], f->last[s]);
        f->added[s] = 0;
    }
    return n;
}

int pk_feedback_tick(pk_feedback *f)
{
    double com[4];
    int com_done = 0;
    return pk_feedback_add(f, com, &com_done);
}
"""[1:]  # (the text from its first line)
