/* bound.c -- the constant C of the error estimation function e_x (paper Eq. 4, Appendix) for the
 * cascade of a path, as computed by libparaxial's bounds (issue 3). Until that module exists
 * the Appendix variants are reported as unavailable and the renderer uses the probe. */
#include "bound.h"

#include <string.h>

px_status_t pt__bound_c(const pt_node_t *nodes, int k, pt_bound_t b, double *out) {
  (void)nodes;
  (void)k;
  (void)b;
  (void)out;
  return PX_EINVAL;
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
