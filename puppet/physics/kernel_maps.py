"""A run of pose grids in the compiled kernel (``pk_grid_run``): a mouse event's maps
on the cat, written operation for operation as ``interface.maps._grid_run``'s Python.

The cat's four legs are four 2 x 3 pose grids on the mouse's x and y; a mouse event
comes every two steps of a trot, and the grids' Python (the corners and weights per
mirror, then each servo's bilinear sum) cost about as much as the physics step
between two events (cat-trot 33 % control overhead). In C it is one call: per mirror
the corners and weights (the same clamps, the same truncation), then per servo
``0.0 + w0 * a0 + w1 * a1 + w2 * a2 + w3 * a3`` in that order, written as its
spring's rest angle (no contraction: ``kernel.FLAGS``), so the targets have the bits
the Python gives.
"""

MAX_MIRRORS = 4  # (x, y, both, none)

MAPS_TYPES = """
typedef struct {
    int n_flips;
    int flip_x[4], flip_y[4];  /* per mirror: 1 - x, 1 - y */
    int rows, cols;
    int n;            /* the servos */
    int *use;         /* per servo: its mirror */
    double *cells;    /* per servo, its rows x cols angles: [(j * rows + r) * cols + c] */
    void **spring;    /* per servo */
} pk_grid_table;
"""

MAPS_CDEF = MAPS_TYPES + """
void pk_grid_run(pk_grid_table *g, double x0, double y0);
"""

MAPS_SOURCE = MAPS_TYPES + r"""
/* maps._grid_run's apply_grid_run, after its inputs are read */
void pk_grid_run(pk_grid_table *g, double x0, double y0)
{
    int last_col = g->cols - 1, last_row = g->rows - 1;
    int r0[4], c0[4], r1[4], c1[4];
    double w[4][4];
    for (int k = 0; k < g->n_flips; k++) {
        double x = g->flip_x[k] ? 1.0 - x0 : x0;
        double y = g->flip_y[k] ? 1.0 - y0 : y0;
        double m = x > 0.0 ? x : 0.0;
        double fx = (m < 1.0 ? m : 1.0) * (double)last_col;
        double fy, tx, ty;
        m = y > 0.0 ? y : 0.0;
        fy = (1.0 - (m < 1.0 ? m : 1.0)) * (double)last_row;
        c0[k] = 0;
        if (g->cols > 1) {
            c0[k] = (int)fx;
            if (c0[k] > g->cols - 2)
                c0[k] = g->cols - 2;
        }
        r0[k] = 0;
        if (g->rows > 1) {
            r0[k] = (int)fy;
            if (r0[k] > g->rows - 2)
                r0[k] = g->rows - 2;
        }
        tx = fx - (double)c0[k];
        ty = fy - (double)r0[k];
        r1[k] = r0[k] + 1 < last_row ? r0[k] + 1 : last_row;
        c1[k] = c0[k] + 1 < last_col ? c0[k] + 1 : last_col;
        w[k][0] = (1.0 - tx) * (1.0 - ty);
        w[k][1] = tx * (1.0 - ty);
        w[k][2] = (1.0 - tx) * ty;
        w[k][3] = tx * ty;
    }
    for (int j = 0; j < g->n; j++) {
        int k = g->use[j];
        const double *a = g->cells + (long)j * g->rows * g->cols;
        double v = 0.0 + w[k][0] * a[r0[k] * g->cols + c0[k]]
            + w[k][1] * a[r0[k] * g->cols + c1[k]]
            + w[k][2] * a[r1[k] * g->cols + c0[k]]
            + w[k][3] * a[r1[k] * g->cols + c1[k]];
        set_rest_angle(g->spring[j], v);
    }
}
"""
