/* bound.c -- the constant C of the error estimation function e_x (paper Eq. 4, Appendix) for the
 * path of a tree node, from libparaxial's bounds (issue 3): the path's cascade is the chain of the
 * steps (interface + transfer) of the node and its ancestors, and px_pencil_constants() evaluates
 * the general cascade form of Appendix (3) with the A-1 coefficients of the chosen variant.
 * Spheres and planes have no third derivative (d_3m = 0). */
#include "bound.h"

#include <math.h>
#include <string.h>

#include "paraxial/bounds.h"

px_status_t pt__bound_c(const pt_node_t *nodes, int k, pt_bound_t b, double *out) {
  const pt_node_t *chain[EX_MAX_STAGES + 1];
  int m = 0;
  for (int x = k; x >= 0; x = nodes[x].parent) {
    if (m > EX_MAX_STAGES)
      return PX_EINVAL;
    chain[m++] = &nodes[x];
  }
  px_element_t elem[3 * (EX_MAX_STAGES + 1)];
  px_cascade_t cas;
  px_cascade_init(&cas, elem, sizeof elem / sizeof elem[0]);
  for (int j = m - 1; j >= 0; j--)
    for (int e = 0; e < chain[j]->nstep; e++) {
      if (cas.n >= cas.cap)
        return PX_ECAPACITY;
      elem[cas.n++] = chain[j]->step[e];
    }
  px_variant_t v = b == PT_BOUND_PRINTED ? PX_VARIANT_PRINTED : PX_VARIANT_CORRECTED;
  px_pencil_t pc;
  px_status_t st = px_pencil_constants(&cas, NULL, v, &pc);
  if (st != PX_OK)
    return st;
  /* the printed variant is verbatim and may be negative: a negative C bounds nothing */
  *out = pc.c > 0.0 ? pc.c : 0.0;
  return PX_OK;
}

/* C of one term: the (xi0, xi0) entry of M^t (lambda_1 P + lambda_2 Q) M with M the norms of the
 * blocks of T_i^b (only mu_2, mu_4 multiply xi0), P = [[a, b/2], [b/2, c]], Q = [[d, e/2],
 * [e/2, f]] and lambda_1, lambda_2 the norms of the blocks A, B of T_i^a (Appendix (3); the same
 * sum as px_pencil_constants). */
static double term_c(const pt_term_t *t) {
  double l1 = px_mat2_norm2(px_mat4_block(t->ta, 0, 0)),
         l2 = px_mat2_norm2(px_mat4_block(t->ta, 0, 1));
  const double *k = t->k;
  double s11 = l1 * k[0] + l2 * k[3], s12 = 0.5 * (l1 * k[1] + l2 * k[4]),
         s22 = l1 * k[2] + l2 * k[5];
  return t->mb * (s11 * t->mb + s12 * t->md) + t->md * (s12 * t->mb + s22 * t->md);
}

px_status_t pt__bound_step(const pt_node_t *parent, px_mat4_t sm, pt_bound_t b, pt_node_t *k,
                           double *out) {
  px_variant_t v = b == PT_BOUND_PRINTED ? PX_VARIANT_PRINTED : PX_VARIANT_CORRECTED;
  k->nterm = 0;
  if (parent) {
    if (parent->nterm + 1 > EX_MAX_STAGES)
      return PX_ECAPACITY;
    for (int i = 0; i < parent->nterm; i++) { /* T_i^a grows by this step */
      k->term[i] = parent->term[i];
      k->term[i].ta = px_mat4_mul(sm, parent->term[i].ta);
    }
    k->nterm = parent->nterm;
    /* the parent's surface: the step is [transfer eps], interface, transfer t */
    int ie = k->nstep == 3 ? 1 : 0;
    const px_element_t *e = &k->step[ie];
    px_coeffs_t c;
    px_status_t st = px_element_coeffs(e, 0.0, v, &c);
    if (st != PX_OK)
      return st;
    pt_term_t *t = &k->term[k->nterm++];
    double eps = ie == 1 ? k->step[0].distance : 0.0; /* B, D of T^b = Tr(eps) T_parent */
    px_mat2_t bb = px_mat2_add(parent->b, px_mat2_scale(parent->d, eps));
    t->mb = px_mat2_norm2(bb);
    t->md = px_mat2_norm2(parent->d);
    t->ta = k->step[ie + 1].t; /* after the interface: the transfer to the node's hit */
    const double kk[6] = {c.a, c.b, c.c, c.d, c.e, c.f};
    for (int j = 0; j < 6; j++)
      t->k[j] = kk[j];
  }
  double sum = 0.0;
  for (int i = 0; i < k->nterm; i++)
    sum += term_c(&k->term[i]);
  if (!isfinite(sum))
    return PX_ENONFINITE;
  *out = sum > 0.0 ? sum : 0.0; /* the printed variant may be negative: that bounds nothing */
  return PX_OK;
}

int pt_bound_parse(const char *name, pt_bound_t *out) {
  static const char *const names[] = {"corrected", "printed", "probe"};
  for (int i = 0; i < 3; i++)
    if (name && strcmp(names[i], name) == 0) {
      *out = (pt_bound_t)i;
      return 1;
    }
  return 0;
}

const char *pt_bound_name(pt_bound_t b) {
  return b == PT_BOUND_CORRECTED ? "corrected" : b == PT_BOUND_PRINTED ? "printed" : "probe";
}
