/* curvature.h -- private to libparaxial: the curvature an element is judged by (status.h,
 * PX_CURVATURE_MAX), the same for its matrix (system.c) and its error coefficients (bounds.c). */
#ifndef PARAXIAL_CURVATURE_H
#define PARAXIAL_CURVATURE_H

#include <math.h>

#include "paraxial/linalg.h"
#include "paraxial/status.h"

/* |Q|_2, the largest |principal curvature| of the symmetric Q; its largest entry where that
 * is already above PX_CURVATURE_MAX, where the squares of the eigenvalue computation would
 * overflow (either way the element is refused as PX_ENONFINITE). */
static inline double px__curvature(px_mat2_t q) {
  double m = fmax(fmax(fabs(q.m[0][0]), fabs(q.m[0][1])), fmax(fabs(q.m[1][0]), fabs(q.m[1][1])));
  return m > PX_CURVATURE_MAX ? m : px_mat2_norm2(q);
}

#endif
