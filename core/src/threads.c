/* threads.c -- how many OpenMP threads a render uses (core/image.h), one rule for every
 * renderer. */
#include "core/image.h"

#ifdef _OPENMP
#include <omp.h>
#endif

int rt_thread_count(int requested) {
#ifdef _OPENMP
  return requested > 0 ? requested : omp_get_max_threads();
#else
  (void)requested;
  return 1;
#endif
}
