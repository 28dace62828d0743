/* STREAM triad a[i] = b[i] + s * c[i] (McCalpin's kernel), for the memory-bandwidth line of docs/results.md.
 *
 * usage: stream_triad [N_DOUBLES [REPEATS]]   (defaults: 40,000,000 doubles per array = 3 x 320 MB, 20 repeats)
 * Prints one line per statistic: "triad_best_GBps X", "triad_median_GBps X". Bytes per triad: 3 x 8 x N (two reads,
 * one write; write-allocate traffic not counted, as in STREAM). Single-threaded unless built with -fopenmp; run one
 * copy per rank (e.g. `mpiexec -n 2 stream_triad`) to measure what 2 ranks can draw together. */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

static int cmp(const void *x, const void *y) {
  double a = *(const double *)x, b = *(const double *)y;
  return (a > b) - (a < b);
}

int main(int argc, char **argv) {
  long n = argc > 1 ? atol(argv[1]) : 40000000L;
  int reps = argc > 2 ? atoi(argv[2]) : 20;
  if (n < 1000 || reps < 1) {
    fprintf(stderr, "usage: stream_triad [N_DOUBLES >= 1000 [REPEATS >= 1]]\n");
    return 1;
  }
  double *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b), *c = malloc(n * sizeof *c);
  double *t = malloc(reps * sizeof *t);
  if (!a || !b || !c || !t) {
    fprintf(stderr, "stream_triad: cannot allocate 3 x %ld doubles\n", n);
    return 2;
  }
  for (long i = 0; i < n; ++i) a[i] = 1.0, b[i] = 2.0, c[i] = 0.5;
  const double s = 3.0;
  for (int r = 0; r < reps; ++r) {
    double t0 = now();
    for (long i = 0; i < n; ++i) a[i] = b[i] + s * c[i];
    t[r] = now() - t0;
  }
  double check = 0;
  for (long i = 0; i < n; i += n / 16) check += a[i];
  qsort(t, reps, sizeof *t, cmp);
  const double bytes = 3.0 * 8.0 * (double)n;
  printf("triad_best_GBps %.3f\n", bytes / t[0] * 1e-9);
  printf("triad_median_GBps %.3f\n", bytes / t[reps / 2] * 1e-9);
  printf("check %.1f\n", check);
  free(a), free(b), free(c), free(t);
  return 0;
}
