/* timing.h -- clocks and medians for the benchmark and figure drivers (speed is measured by
 * commands, median of several runs, never by a timed test). */
#ifndef VALIDATION_TIMING_H
#define VALIDATION_TIMING_H

/** Monotonic wall-clock seconds (CLOCK_MONOTONIC). */
double val_wall_seconds(void);
/** CPU seconds of the whole process, all threads (CLOCK_PROCESS_CPUTIME_ID). */
double val_cpu_seconds(void);
/** Median of v[0..n-1], n >= 1; sorts v in place. */
double val_median(double *v, int n);

#endif
