/* trace.c -- the axial ray of an exact system, and the paraxial cascade built from it
 * (section 2.2: an overall system matrix is the product of element matrices). */
#include "exact/trace.h"

#include <math.h>

/* Axial roots closer than this (relative to the path scale) to the current point are the
 * current point itself and are skipped, unless the stage says the hit is at the origin. */
#define SELF_HIT 1e-9

static double stage_index(const ex_system_t *sys, size_t k) {
  return k == 0 ? sys->n0
                : (sys->stage[k - 1].event == PX_EVENT_REFLECT ? stage_index(sys, k - 1)
                                                               : sys->stage[k - 1].n_after);
}

/* Roots of F(o + t d) = a t^2 + 2 bb t + c, sorted; returns how many (0, 1 or 2). */
static int quadric_roots(const ex_quadric_t *q, px_vec3_t o, px_vec3_t d, double r[2]) {
  px_vec3_t md = px_vec3_sub(ex_quadric_half_gradient(q, d), px_vec3(q->b[0], q->b[1], q->b[2]));
  double a = px_vec3_dot(d, md);
  double bb = px_vec3_dot(d, ex_quadric_half_gradient(q, o));
  double c = ex_quadric_eval(q, o);
  double scale = fabs(bb) + fabs(a);
  if (fabs(a) <= 1e-14 * scale) { /* linear: a plane, or along a cylinder's axis */
    if (bb == 0.0)
      return 0;
    r[0] = -c / (2.0 * bb);
    return 1;
  }
  double disc = bb * bb - a * c;
  if (disc < 0.0)
    return 0;
  double qq = -(bb + copysign(sqrt(disc), bb));
  double t1 = qq / a, t2 = qq != 0.0 ? c / qq : t1;
  r[0] = fmin(t1, t2);
  r[1] = fmax(t1, t2);
  return 2;
}

px_status_t ex_trace_axial(const ex_system_t *sys, ex_axial_t *ax) {
  if (sys->nstage > EX_MAX_STAGES || !(sys->n0 > 0.0))
    return PX_EINVAL;
  px_vec3_t p = sys->origin;
  px_frame_t frame = sys->frame;
  double length = 0.0;
  for (size_t k = 0; k < sys->nstage; k++) {
    const ex_stage_t *st = &sys->stage[k];
    double r[2], t;
    int nr = quadric_roots(&st->surface, p, frame.z, r);
    if (nr == 0)
      return PX_EMISS;
    double eps = SELF_HIT * (1.0 + length + px_vec3_norm(p));
    if (st->at_origin) { /* the root nearest the current point */
      t = (nr == 2 && fabs(r[1]) < fabs(r[0])) ? r[1] : r[0];
    } else if (r[0] > eps) {
      t = r[0];
    } else if (nr == 2 && r[1] > eps) {
      t = r[1];
    } else {
      return PX_EMISS;
    }
    p = px_vec3_axpy(t, frame.z, p);
    length += fabs(t);
    double n1 = stage_index(sys, k);
    double n2 = st->event == PX_EVENT_REFLECT ? n1 : st->n_after;
    px_status_t s = ex_quadric_interface(&st->surface, p, frame.z, frame.x2, n1, n2, &ax->ifc[k]);
    if (s != PX_OK)
      return s;
    px_frame_t in_canon, out;
    s = px_interface_frames(&ax->ifc[k], st->event, &in_canon, &out);
    if (s != PX_OK)
      return s;
    if (k + 1 == sys->nstage)
      out = px_frame_rotate(out, sys->out_phi);
    ax->t[k] = t;
    ax->hit[k] = p;
    ax->in[k] = frame;
    ax->out[k] = out;
    frame = out;
  }
  ax->n = sys->nstage;
  ax->out_origin = px_vec3_axpy(sys->tail, frame.z, p);
  ax->out_frame = frame;
  ax->length = length + fabs(sys->tail);
  return PX_OK;
}

px_status_t ex_axial_cascade(const ex_system_t *sys, const ex_axial_t *ax, px_variant_t variant,
                             px_element_t *storage, size_t cap, px_cascade_t *out) {
  px_cascade_init(out, storage, cap);
  px_status_t s = PX_OK;
  for (size_t k = 0; k < ax->n && s == PX_OK; k++) {
    if (ax->t[k] != 0.0)
      s = px_cascade_push_transfer(out, ax->t[k], ax->in[k]);
    if (s == PX_OK)
      s = px_cascade_push_interface(out, &ax->ifc[k], sys->stage[k].event, ax->in[k], ax->out[k],
                                    variant);
  }
  if (s == PX_OK && sys->tail != 0.0)
    s = px_cascade_push_transfer(out, sys->tail, ax->out_frame);
  return s;
}
