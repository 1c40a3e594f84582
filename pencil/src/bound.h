/* bound.h -- private: the constant C of Eq. (4) for a path's cascade, from libparaxial's error
 * bounds (Appendix, issue 3). */
#ifndef PENCIL_BOUND_H
#define PENCIL_BOUND_H

#include "pencil/path.h"

/** C of e_x (Eq. 4) for a pinhole pencil entering the path of node k, whose cascade is the chain
 *  of the steps of k and its ancestors: PT_BOUND_CORRECTED or PT_BOUND_PRINTED. PX_EINVAL when
 *  the variant is not available. */
px_status_t pt__bound_c(const pt_node_t *nodes, int k, pt_bound_t b, double *out);

#endif
