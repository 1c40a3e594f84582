/* timing.c -- clocks, medians and --case lists for the benchmark and figure drivers. */
#include "validation/timing.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double seconds(clockid_t id) {
  struct timespec t;
  clock_gettime(id, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

double val_wall_seconds(void) {
  return seconds(CLOCK_MONOTONIC);
}
double val_cpu_seconds(void) {
  return seconds(CLOCK_PROCESS_CPUTIME_ID);
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

void val_sort(double *v, size_t n) {
  qsort(v, n, sizeof v[0], cmp_double);
}

double val_quantile(const double *v, size_t n, double q) {
  return n ? v[(size_t)floor(q * (double)(n - 1))] : NAN;
}

double val_median(double *v, int n) {
  qsort(v, (size_t)n, sizeof v[0], cmp_double);
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int val_case_listed(const char *list, const char *name) {
  if (!list)
    return 1;
  size_t n = strlen(name);
  for (const char *p = list; *p;) {
    size_t k = strcspn(p, ",");
    if (k == n && strncmp(p, name, n) == 0)
      return 1;
    p += k + (p[k] == ',');
  }
  return 0;
}

int val_case_list_ok(const char *list, const char *const *names, int n, char *bad, size_t cap) {
  for (const char *p = list;;) { /* every item a name: "" and a trailing comma's are not */
    size_t k = strcspn(p, ",");
    int known = 0;
    for (int c = 0; c < n; c++)
      known |= strlen(names[c]) == k && strncmp(p, names[c], k) == 0;
    if (!known) {
      snprintf(bad, cap, "%.*s", (int)k, p);
      return 0;
    }
    if (!p[k])
      return 1;
    p += k + 1;
  }
}
