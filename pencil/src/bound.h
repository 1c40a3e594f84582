/* bound.h -- private: the constant C of Eq. (4) for a path's cascade, from libparaxial's error
 * bounds (Appendix, issue 3). */
#ifndef PENCIL_BOUND_H
#define PENCIL_BOUND_H

#include "pencil/path.h"

/** C of e_x (Eq. 4) for a pinhole pencil entering the path of node k, whose cascade is the chain
 *  of the steps of k and its ancestors, by px_pencil_constants() on the assembled cascade
 *  (O(n^2) in the path length; the reference for pt__bound_step). */
px_status_t pt__bound_c(const pt_node_t *nodes, int k, pt_bound_t b, double *out);

/** The same, incrementally: node k's terms from its parent's (`parent`, NULL for the primary
 *  ray) and its step (product sm = the step's cascade product, elements in k->step), then
 *  C = the sum of the terms (Appendix (3) with zeta = (0, xi0)). */
px_status_t pt__bound_step(const pt_node_t *parent, px_mat4_t sm, pt_bound_t b, pt_node_t *k,
                           double *out);

#endif
