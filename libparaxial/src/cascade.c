/* cascade.c -- cascades T = Tn ... T1 and the partial products T_i^a, T_i^b of Appendix (3). */
#include "paraxial/cascade.h"

#include <math.h>
#include <string.h>

void px_cascade_init(px_cascade_t *c, px_element_t *storage, size_t cap) {
  c->elem = storage;
  c->n = 0;
  c->cap = cap;
}

static px_element_t *next_slot(px_cascade_t *c) {
  if (c->n >= c->cap)
    return NULL;
  px_element_t *e = &c->elem[c->n];
  memset(e, 0, sizeof *e);
  return e;
}

px_status_t px_cascade_push_transfer(px_cascade_t *c, double d, px_frame_t frame) {
  if (!isfinite(d))
    return PX_EINVAL;
  px_element_t *e = next_slot(c);
  if (!e)
    return PX_ECAPACITY;
  e->kind = PX_ELEMENT_TRANSFER;
  e->t = px_transfer_matrix(d);
  e->distance = d;
  e->in = e->out = frame;
  c->n++;
  return PX_OK;
}

px_status_t px_cascade_push_interface(px_cascade_t *c, const px_interface_t *ifc, px_event_t ev,
                                      px_frame_t in, px_frame_t out, px_variant_t variant) {
  if (c->n >= c->cap)
    return PX_ECAPACITY;
  px_mat4_t t;
  px_status_t st = px_interface_matrix(ifc, ev, in, out, variant, &t);
  if (st != PX_OK)
    return st;
  px_element_t *e = next_slot(c);
  e->kind = ev == PX_EVENT_REFLECT ? PX_ELEMENT_REFLECT : PX_ELEMENT_REFRACT;
  e->t = t;
  e->ifc = *ifc;
  e->in = in;
  e->out = out;
  c->n++;
  return PX_OK;
}

/* product T_hi ... T_lo of 1-based indices lo..hi (identity when lo > hi) */
static px_mat4_t range_product(const px_cascade_t *c, size_t lo, size_t hi) {
  px_mat4_t r = px_mat4_identity();
  for (size_t i = lo; i <= hi && i <= c->n; i++)
    r = px_mat4_mul(c->elem[i - 1].t, r);
  return r;
}

px_mat4_t px_cascade_product(const px_cascade_t *c) {
  return range_product(c, 1, c->n);
}
px_mat4_t px_cascade_product_abs(const px_cascade_t *c) {
  px_mat4_t r = px_mat4_identity();
  for (size_t i = 0; i < c->n; i++) {
    px_mat4_t a = c->elem[i].t;
    for (int j = 0; j < 4; j++)
      for (int k = 0; k < 4; k++)
        a.m[j][k] = fabs(a.m[j][k]);
    r = px_mat4_mul(a, r);
  }
  return r;
}

px_mat4_t px_cascade_after(const px_cascade_t *c, size_t i) {
  return range_product(c, i + 1, c->n);
}
px_mat4_t px_cascade_before(const px_cascade_t *c, size_t i) {
  return i <= 1 ? px_mat4_identity() : range_product(c, 1, i - 1);
}
