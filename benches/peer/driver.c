/* The CasADi peer's driver: a dense Newton on the generated energy, its
 * gradient and Hessian (ccm_gen.c, written by build_peer.py), timing the
 * two tip-loaded cases of `fpc-lab timing`.
 *
 * Usage: driver [REPS]   (default 2000 timed solves per case)
 *
 * Newton stops as fpc does by default: the scaled gradient's largest entry
 * at most 1e-11 times the stiffness scale. Each step solves H d = -g by
 * Cholesky (LU with partial pivoting where H is not positive definite),
 * is capped at 0.25 in the scaled unknowns, and backtracks on the energy
 * (Armijo) where the full step does not lower it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "ccm_gen.h"
#include "peer_case.h"

#define NU (4 * PEER_N)
#define RTOL 1e-11
#define MAX_ITER 60
#define MAX_STEP 0.25

static casadi_int iw_buf[4096];
static double *w_all, *w_energy, *w_tip;

static double wall_us(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec * 1e6 + t.tv_nsec * 1e-3;
}

static double *work(int (*size)(casadi_int *, casadi_int *, casadi_int *, casadi_int *)) {
  casadi_int a, r, i, w;
  size(&a, &r, &i, &w);
  if (i > 4096 || a > 8 || r > 8) {
    fprintf(stderr, "driver: generated function needs more work space than provided\n");
    exit(2);
  }
  return malloc(sizeof(double) * (size_t)(w > 0 ? w : 1));
}

/* energy, gradient and Hessian (column-major; symmetric) at y */
static void eval_all(const double *y, const double *p, double *pi, double *g, double *h) {
  const double *arg[8] = {y, p};
  double *res[8] = {pi, g, h};
  ccm_all(arg, res, iw_buf, w_all, 0);
}

static double eval_energy(const double *y, const double *p) {
  const double *arg[8] = {y, p};
  double pi;
  double *res[8] = {&pi};
  ccm_energy(arg, res, iw_buf, w_energy, 0);
  return pi;
}

/* in-place Cholesky of the lower triangle; 0 when not positive definite */
static int cholesky(double *a, int n) {
  for (int j = 0; j < n; j++) {
    double d = a[j * n + j];
    for (int k = 0; k < j; k++) d -= a[j * n + k] * a[j * n + k];
    if (!(d > 0.0)) return 0;
    d = sqrt(d);
    a[j * n + j] = d;
    for (int i = j + 1; i < n; i++) {
      double s = a[i * n + j];
      for (int k = 0; k < j; k++) s -= a[i * n + k] * a[j * n + k];
      a[i * n + j] = s / d;
    }
  }
  return 1;
}

static void cholesky_solve(const double *l, int n, double *x) {
  for (int i = 0; i < n; i++) {
    double s = x[i];
    for (int k = 0; k < i; k++) s -= l[i * n + k] * x[k];
    x[i] = s / l[i * n + i];
  }
  for (int i = n - 1; i >= 0; i--) {
    double s = x[i];
    for (int k = i + 1; k < n; k++) s -= l[k * n + i] * x[k];
    x[i] = s / l[i * n + i];
  }
}

/* LU with partial pivoting, solving a x = b in place; 0 when singular */
static int lu_solve(double *a, int n, double *b) {
  for (int j = 0; j < n; j++) {
    int piv = j;
    for (int i = j + 1; i < n; i++)
      if (fabs(a[i * n + j]) > fabs(a[piv * n + j])) piv = i;
    if (a[piv * n + j] == 0.0) return 0;
    if (piv != j) {
      for (int k = 0; k < n; k++) {
        double t = a[j * n + k];
        a[j * n + k] = a[piv * n + k];
        a[piv * n + k] = t;
      }
      double t = b[j];
      b[j] = b[piv];
      b[piv] = t;
    }
    for (int i = j + 1; i < n; i++) {
      double f = a[i * n + j] / a[j * n + j];
      a[i * n + j] = f;
      for (int k = j + 1; k < n; k++) a[i * n + k] -= f * a[j * n + k];
      b[i] -= f * b[j];
    }
  }
  for (int i = n - 1; i >= 0; i--) {
    double s = b[i];
    for (int k = i + 1; k < n; k++) s -= a[i * n + k] * b[k];
    b[i] = s / a[i * n + i];
  }
  return 1;
}

static double norm_inf(const double *v, int n) {
  double m = 0.0;
  for (int i = 0; i < n; i++) m = fmax(m, fabs(v[i]));
  return m;
}

/* Newton from y (scaled unknowns, overwritten with the solution); the
 * number of iterations, or -1 when it does not converge. */
static int newton(double *y, const double *p, double *residual) {
  static double g[NU], h[NU * NU], a[NU * NU], d[NU], yt[NU], gt[NU], ht[NU * NU];
  double pi, pit;
  const double tol = RTOL * PEER_STIFFNESS;
  eval_all(y, p, &pi, g, h);
  for (int it = 0; it <= MAX_ITER; it++) {
    double r = norm_inf(g, NU);
    if (r <= tol) {
      *residual = r / PEER_STIFFNESS;
      return it;
    }
    if (it == MAX_ITER) break;
    memcpy(a, h, sizeof(a));
    for (int i = 0; i < NU; i++) d[i] = -g[i];
    int descent = cholesky(a, NU);
    if (descent) {
      cholesky_solve(a, NU, d);
    } else {
      memcpy(a, h, sizeof(a));
      if (!lu_solve(a, NU, d)) return -1;
    }
    double s = norm_inf(d, NU);
    if (s > MAX_STEP)
      for (int i = 0; i < NU; i++) d[i] *= MAX_STEP / s;
    double gd = 0.0;
    for (int i = 0; i < NU; i++) gd += g[i] * d[i];
    double t = 1.0;
    for (int i = 0; i < NU; i++) yt[i] = y[i] + d[i];
    eval_all(yt, p, &pit, gt, ht);
    /* Armijo on the energy; a rise at the level of round-off is accepted */
    if (descent && gd < 0.0) {
      double slack = 1e-13 * fabs(pi);
      while (pit > pi + 1e-4 * t * gd + slack && t > 1e-8) {
        t *= 0.5;
        for (int i = 0; i < NU; i++) yt[i] = y[i] + t * d[i];
        pit = eval_energy(yt, p);
      }
      if (t < 1.0) eval_all(yt, p, &pit, gt, ht);
    }
    memcpy(y, yt, sizeof(yt));
    memcpy(g, gt, sizeof(gt));
    memcpy(h, ht, sizeof(ht));
    pi = pit;
  }
  return -1;
}

static int cmp(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* median wall time (us) of reps solves from start; the last solution in y */
static double time_solve(const double *start, const double *p, int reps, double *y, int *iters,
                         double *residual) {
  double *t = malloc(sizeof(double) * (size_t)reps);
  for (int r = 0; r < reps; r++) {
    memcpy(y, start, sizeof(double) * NU);
    double t0 = wall_us();
    *iters = newton(y, p, residual);
    t[r] = wall_us() - t0;
    if (*iters < 0) {
      fprintf(stderr, "driver: Newton did not converge\n");
      exit(1);
    }
  }
  qsort(t, (size_t)reps, sizeof(double), cmp);
  double m = t[reps / 2];
  free(t);
  return m;
}

static void solve_or_die(double *y, const double *p, const char *what) {
  double r;
  if (newton(y, p, &r) < 0) {
    fprintf(stderr, "driver: Newton did not converge (%s)\n", what);
    exit(1);
  }
}

int main(int argc, char **argv) {
  int reps = argc > 1 ? atoi(argv[1]) : 2000;
  if (reps < 1) {
    fprintf(stderr, "driver: REPS must be a positive integer, got `%s`\n", argv[1]);
    return 2;
  }
  w_all = work(ccm_all_work);
  w_energy = work(ccm_energy_work);
  w_tip = work(ccm_tip_work);

  /* the starts, untimed: the unloaded equilibrium (from the straight
   * finger) and the equilibrium at 95 % of the loads (from the unloaded) */
  const double p0[3] = {0.0, 0.0, 0.0};
  const double p95[3] = {0.0, 0.95 * PEER_FX, 0.95 * PEER_FZ};
  const double p[3] = {0.0, PEER_FX, PEER_FZ};
  static double unloaded[NU], near[NU], y[NU];
  solve_or_die(unloaded, p0, "unloaded, from the straight finger");
  memcpy(near, unloaded, sizeof(near));
  solve_or_die(near, p95, "95 % of the loads, from the unloaded");

  int it_cold, it_warm;
  double res_cold, res_warm;
  /* one untimed solve of each warms the caches */
  time_solve(unloaded, p, 1, y, &it_cold, &res_cold);
  double cold = time_solve(unloaded, p, reps, y, &it_cold, &res_cold);
  double warm = time_solve(near, p, reps, y, &it_warm, &res_warm);
  /* the reported state: the cold solve's */
  time_solve(unloaded, p, 1, y, &it_cold, &res_cold);

  double tip[2];
  const double *arg[8] = {y};
  double *res[8] = {tip};
  ccm_tip(arg, res, iw_buf, w_tip, 0);

  printf("elements %d\n", PEER_N);
  printf("reps %d\n", reps);
  printf("cold_solve_us %.3f\n", cold);
  printf("cold_iterations %d\n", it_cold);
  printf("cold_residual %.3e\n", res_cold);
  printf("warm_solve_us %.3f\n", warm);
  printf("warm_iterations %d\n", it_warm);
  printf("warm_residual %.3e\n", res_warm);
  printf("tip_x_mm %.17g\n", tip[0]);
  printf("tip_z_mm %.17g\n", tip[1]);
  /* the raw element unknowns K_i = (a1, a3, b1, c2) */
  for (int i = 0; i < PEER_N; i++)
    printf("element %d %.17g %.17g %.17g %.17g\n", i + 1, y[4 * i] * PEER_UNSCALE[0],
           y[4 * i + 1] * PEER_UNSCALE[1], y[4 * i + 2] * PEER_UNSCALE[2],
           y[4 * i + 3] * PEER_UNSCALE[3]);
  return 0;
}
