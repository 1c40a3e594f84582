/* timing.h -- clocks, medians and --case lists for the benchmark and figure drivers (speed is
 * measured by commands, median of several runs, never by a timed test). */
#ifndef VALIDATION_TIMING_H
#define VALIDATION_TIMING_H

#include <stddef.h>

/** Monotonic wall-clock seconds (CLOCK_MONOTONIC). */
double val_wall_seconds(void);
/** CPU seconds of the whole process, all threads (CLOCK_PROCESS_CPUTIME_ID). */
double val_cpu_seconds(void);
/** Median of v[0..n-1], n >= 1; sorts v in place. */
double val_median(double *v, int n);
/** Sort v[0..n-1] ascending. */
void val_sort(double *v, size_t n);
/** The q-quantile (0 <= q <= 1) of sorted v[0..n-1] as the benchmarks report it: v[floor(q (n -
 * 1))]; NaN for n = 0. */
double val_quantile(const double *v, size_t n, double q);

/** 1 when `name` is an entry of the comma-separated list (NULL: every name is): a benchmark's
 *  --case option. */
int val_case_listed(const char *list, const char *name);
/** 1 when every entry of the comma-separated list is one of names[0 .. n-1]; else 0 with the
 *  first unknown entry in bad[cap]. */
int val_case_list_ok(const char *list, const char *const *names, int n, char *bad, size_t cap);

#endif
