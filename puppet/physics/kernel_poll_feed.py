"""The C of feedback's add maps following a state machine inside ``pk_poll``'s loop: a
state whose maps are add maps on sensors (a Luxo flip's ``tucked`` and ``landed``:
the centre of mass's fall time, the base's angle and spin) entered and left between
Chipmunk's steps (``kernel_poll_states``), its maps' rows switched into the loop's
``pk_feedback`` as ``Feedback.set_maps`` switches the compiled plan.

Python's tick at a step where a transition holds runs the controllers first (the
blend's write, then ``Feedback.tick`` with the maps of the state it is leaving), then
``_enter_state``: the new state's maps (``_refresh_active_maps``: from the next
control step on), its entry (``BlendController.start``, which writes every travelling
target again). So ``pk_transit`` makes the tick's add before its entries
(``pk_feed_tick``), and ``pk_tick`` does not add again at that step. A state left
with its additions still held (``Feedback.last``) has them taken back at the next
control step by the add with no rows, as Python's tick does with no maps. Each
state's rows that ran are logged (kind 4) when it is left, so that
``interface.poll_feed`` hands the sensors' last readings back in Python's order.
Kept apart from ``kernel_poll_states`` (the states table) and ``kernel_control``
(the add itself, ``pk_feedback_add``).
"""

FEED_SOURCE = r"""
/* Feedback.tick at ``s`` with the rows p->feedback has (the state's, kernel_control's
   pk_feedback_add), the centre of mass shared with the tick's polls */
static void pk_feed_tick(pk_poll_plan *p, pk_states *st, int s, pk_com_now *com)
{
    pk_feedback_add(p->feedback, com->v, &com->done);
    p->fb_ticks++;
    st->fb_ran = 1;
    st->fb_at = s;
}

/* state ``b`` entered at ``s``: its maps' rows (none: n_rows 0, the additions held
   taken back at the next tick), the rows it leaves logged if they ran */
static void pk_feed_enter(pk_poll_plan *p, pk_states *st, int b, int s)
{
    pk_feedback *f = p->feedback;
    const pk_feedback *t = st->e_fb[b];
    if (st->fb_ran)
        pk_log(st, s, 4, st->fb_state);
    st->fb_state = b;
    st->fb_ran = 0;
    if (!t) {
        f->n_sensors = f->n_rows = 0;
        return;
    }
    f->n_sensors = t->n_sensors;
    f->kind = t->kind;
    f->a = t->a;
    f->b = t->b;
    f->values = t->values;
    f->n_rows = t->n_rows;
    f->sensor = t->sensor;
    f->clamp = t->clamp;
    f->slot = t->slot;
    f->x0 = t->x0;
    f->inv = t->inv;
    f->lo = t->lo;
    f->span = t->span;
    f->gain = t->gain;
}
"""
