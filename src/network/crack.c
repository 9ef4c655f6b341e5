/* crack.c: the pre-cracks and holes that cut arms (ps_network.h): 2D
 * crack segments, 3D planar crack polygons and 3D spherical holes, their
 * set-up (a polygon's plane) and the test ps_crack_cuts. Units: m. */
#include "ps_network.h"

#include <math.h>
#include <string.h>

static double dot3(const double *a, const double *b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The plane of the points v[0..n) but v[skip] (skip < 0: all): o the
 * centroid of the points, s their largest distance from it, and Newell's
 * area vector A = 1/2 sum_i (v_i - o) x (v_(i+1) - o) over the polygon
 * they form in order (exact for a planar polygon: its area times its
 * normal; for a nearly planar one the normal that weighs the outline's
 * projections). Returns |A|; nrm = A / |A| when |A| > 0. */
static double plane_of(const double (*v)[3], int n, int skip, double o[3], double nrm[3],
                       double *s) {
  int m = 0, idx[PS_CRACK_MAX_VERTICES];
  for (int i = 0; i < n; i++)
    if (i != skip) idx[m++] = i;
  o[0] = o[1] = o[2] = 0;
  for (int j = 0; j < m; j++)
    for (int k = 0; k < 3; k++) o[k] += v[idx[j]][k] / m;
  *s = 0;
  double A[3] = {0, 0, 0};
  for (int j = 0; j < m; j++) {
    const double *p = v[idx[j]], *q = v[idx[(j + 1) % m]];
    double a[3] = {p[0] - o[0], p[1] - o[1], p[2] - o[2]};
    double b[3] = {q[0] - o[0], q[1] - o[1], q[2] - o[2]};
    double c[3];
    ps_cross3(a, b, c);
    for (int k = 0; k < 3; k++) A[k] += 0.5 * c[k];
    *s = fmax(*s, sqrt(dot3(a, a)));
  }
  double area = sqrt(dot3(A, A));
  for (int k = 0; k < 3; k++) nrm[k] = area > 0 ? A[k] / area : 0;
  return area;
}

/* distance of the point x from the plane through o with unit normal nrm */
static double off_plane(const double *x, const double *o, const double *nrm) {
  double d[3] = {x[0] - o[0], x[1] - o[1], x[2] - o[2]};
  return fabs(dot3(d, nrm));
}

/* ps_network.h */
int ps_crack_polygon(ps_crack *cr, int n, const double (*v)[3], int *bad, ps_ctx *ctx) {
  *bad = -1;
  if (n < 3 || n > PS_CRACK_MAX_VERTICES)
    return ps_error(ctx, PS_ERR_INPUT, "a crack polygon has 3 to %d points (got %d)",
                    PS_CRACK_MAX_VERTICES, n);
  for (int i = 0; i < n; i++)
    for (int k = 0; k < 3; k++)
      if (!isfinite(v[i][k])) {
        *bad = i;
        return ps_error(ctx, PS_ERR_INPUT, "point %d: coordinate not finite", i + 1);
      }
  memset(cr, 0, sizeof *cr);
  cr->kind = PS_CRACK_POLYGON;
  cr->n = n;
  memcpy(cr->v, v, sizeof(double[3]) * (size_t)n);
  double s, area = plane_of(v, n, -1, cr->o, cr->nrm, &s);
  if (!(area > PS_CRACK_FLAT * s * s))
    return ps_error(ctx, PS_ERR_INPUT,
                    "zero area (%g m^2 for a polygon of size %g m): its points coincide "
                    "or lie on a line",
                    area, s);
  double dmax = 0;
  for (int i = 0; i < n; i++) dmax = fmax(dmax, off_plane(v[i], cr->o, cr->nrm));
  if (dmax > PS_CRACK_FLAT * s) {
    /* name the point off the plane of the others: the one whose removal
     * leaves the rest most nearly planar (ties: the farthest from it) */
    int worst = 0;
    double best = INFINITY, far = 0;
    for (int i = 0; i < n; i++) {
      double o[3], nrm[3], si, res = 0;
      if (!(plane_of(v, n, i, o, nrm, &si) > PS_CRACK_FLAT * si * si)) continue;
      for (int j = 0; j < n; j++)
        if (j != i) res = fmax(res, off_plane(v[j], o, nrm));
      double dist = off_plane(v[i], o, nrm);
      if (res < best * (1 - 1e-9) || (res <= best * (1 + 1e-9) && dist > far)) {
        best = res;
        far = dist;
        worst = i;
      }
    }
    *bad = worst;
    return ps_error(ctx, PS_ERR_INPUT,
                    "not planar: point %d (%g, %g, %g) is %g m off the plane of the others "
                    "(allowed: %g of the polygon's size %g m)",
                    worst + 1, v[worst][0], v[worst][1], v[worst][2], far, PS_CRACK_FLAT, s);
  }
  /* in-plane axes: e1 = the unit vector normal to nrm in the plane of
   * nrm and the coordinate axis least aligned with it, e2 = nrm x e1 */
  int ax = 0;
  for (int k = 1; k < 3; k++)
    if (fabs(cr->nrm[k]) < fabs(cr->nrm[ax])) ax = k;
  double t[3] = {0, 0, 0};
  t[ax] = 1;
  ps_cross3(cr->nrm, t, cr->e2);
  double l2 = sqrt(dot3(cr->e2, cr->e2));
  for (int k = 0; k < 3; k++) cr->e2[k] /= l2;
  ps_cross3(cr->e2, cr->nrm, cr->e1);
  for (int i = 0; i < n; i++) {
    double d[3] = {v[i][0] - cr->o[0], v[i][1] - cr->o[1], v[i][2] - cr->o[2]};
    cr->uv[i][0] = dot3(d, cr->e1);
    cr->uv[i][1] = dot3(d, cr->e2);
  }
  return PS_OK;
}

/* ps_network.h */
void ps_crack_sphere(ps_crack *cr, const double *c, double R) {
  memset(cr, 0, sizeof *cr);
  cr->kind = PS_CRACK_SPHERE;
  for (int k = 0; k < 3; k++) cr->p0[k] = c[k];
  cr->radius = R;
}

/* ps_network.h */
void ps_crack_bounds(const ps_crack *cr, int dim, double lo[3], double hi[3]) {
  for (int k = 0; k < dim; k++) {
    switch (cr->kind) {
    case PS_CRACK_POLYGON:
      lo[k] = hi[k] = cr->v[0][k];
      for (int i = 1; i < cr->n; i++) {
        lo[k] = fmin(lo[k], cr->v[i][k]);
        hi[k] = fmax(hi[k], cr->v[i][k]);
      }
      break;
    case PS_CRACK_SPHERE:
      lo[k] = cr->p0[k] - cr->radius;
      hi[k] = cr->p0[k] + cr->radius;
      break;
    default:
      lo[k] = fmin(cr->p0[k], cr->p1[k]);
      hi[k] = fmax(cr->p0[k], cr->p1[k]);
    }
  }
}

/* ps_network.h */
int ps_cracks_check(const ps_crack *cracks, int n, int dim, ps_ctx *ctx) {
  static const char *const what[] = {"a segment", "a polygon", "a sphere"};
  for (int c = 0; c < n; c++) {
    int kind = cracks[c].kind;
    int known = kind >= PS_CRACK_SEGMENT && kind <= PS_CRACK_SPHERE;
    int fits = known && (dim == 2) == (kind == PS_CRACK_SEGMENT) &&
               (kind != PS_CRACK_POLYGON ||
                (cracks[c].n >= 3 && cracks[c].n <= PS_CRACK_MAX_VERTICES));
    if (!fits)
      return ps_error(ctx, PS_ERR_INPUT,
                      "crack %d: %s in a %dD network (2D: segments; 3D: planar polygons "
                      "of 3 to %d points and spheres)",
                      c + 1, known ? what[kind] : "an unknown kind", dim,
                      PS_CRACK_MAX_VERTICES);
  }
  return PS_OK;
}

/* the 2D segment rule (ps_crack_cuts) */
static int segment_cuts(const ps_crack *cr, const double *x, const double *y) {
  const double *p = cr->p0, *q = cr->p1;
  double ux = q[0] - p[0], uy = q[1] - p[1], lu = hypot(ux, uy);
  double ex = y[0] - x[0], ey = y[1] - x[1];
  double tol = PS_CRACK_TOUCH * hypot(ex, ey);
  if (!(lu > 0)) return 0; /* a point: cuts nothing */
  /* signed distances of the arm's ends from the crack's line: the ends
   * must lie on opposite sides, each farther than tol */
  double dx = (ux * (x[1] - p[1]) - uy * (x[0] - p[0])) / lu;
  double dy = (ux * (y[1] - p[1]) - uy * (y[0] - p[0])) / lu;
  if (!((dx > tol && dy < -tol) || (dx < -tol && dy > tol))) return 0;
  /* the arm meets the crack's line at x + t (y - x), t = dx / (dx - dy) in
   * (0, 1); sigma = that point's distance from p0 along the crack. Cut
   * when it lies inside the open segment (p0, p1) by more than tol: an
   * arm through an end point (to round-off) is kept */
  double t = dx / (dx - dy);
  double sigma = ((x[0] - p[0] + t * ex) * ux + (x[1] - p[1] + t * ey) * uy) / lu;
  return sigma > tol && sigma < lu - tol;
}

/* Is the point (u, v) of the plane inside the polygon uv[0..n) (even-odd
 * crossing number: a ray from it in +u crosses the outline an odd number
 * of times) and farther than tol from each of its edges? */
static int inside_polygon(const double (*uv)[2], int n, double u, double v, double tol) {
  int in = 0;
  for (int i = 0, j = n - 1; i < n; j = i++) {
    double ui = uv[i][0], vi = uv[i][1], uj = uv[j][0], vj = uv[j][1];
    /* distance from (u, v) to the edge j-i */
    double eu = ui - uj, ev = vi - vj, ee = eu * eu + ev * ev;
    double s = ee > 0 ? ((u - uj) * eu + (v - vj) * ev) / ee : 0;
    s = s < 0 ? 0 : s > 1 ? 1 : s;
    if (hypot(u - uj - s * eu, v - vj - s * ev) <= tol) return 0;
    /* the edge crosses the horizontal line through v to the right of u */
    if ((vi > v) != (vj > v) && u < uj + (v - vj) * eu / ev) in = !in;
  }
  return in;
}

/* the 3D polygon rule (ps_crack_cuts), x before y lexicographically */
static int polygon_cuts(const ps_crack *cr, const double *x, const double *y) {
  double e[3] = {y[0] - x[0], y[1] - x[1], y[2] - x[2]};
  double tol = PS_CRACK_TOUCH * sqrt(dot3(e, e));
  /* signed distances of the ends from the plane: opposite sides, each
   * farther than tol */
  double dx[3] = {x[0] - cr->o[0], x[1] - cr->o[1], x[2] - cr->o[2]};
  double sx = dot3(dx, cr->nrm), sy = sx + dot3(e, cr->nrm);
  if (!((sx > tol && sy < -tol) || (sx < -tol && sy > tol))) return 0;
  /* the arm meets the plane at x + t e, t = sx / (sx - sy) in (0, 1) */
  double t = sx / (sx - sy), r[3];
  for (int k = 0; k < 3; k++) r[k] = dx[k] + t * e[k];
  return inside_polygon((const double(*)[2])cr->uv, cr->n, dot3(r, cr->e1),
                        dot3(r, cr->e2), tol);
}

/* the 3D sphere rule (ps_crack_cuts), x before y lexicographically:
 * closest point x + t e, t = (c - x).e / e.e clamped to [0, 1] */
static int sphere_cuts(const ps_crack *cr, const double *x, const double *y) {
  double e[3] = {y[0] - x[0], y[1] - x[1], y[2] - x[2]};
  double w[3] = {cr->p0[0] - x[0], cr->p0[1] - x[1], cr->p0[2] - x[2]};
  double ee = dot3(e, e), t = ee > 0 ? dot3(w, e) / ee : 0;
  t = t < 0 ? 0 : t > 1 ? 1 : t;
  double d[3] = {w[0] - t * e[0], w[1] - t * e[1], w[2] - t * e[2]};
  return sqrt(dot3(d, d)) < cr->radius;
}

/* ps_network.h */
int ps_crack_cuts(const ps_crack *cr, const double *x, const double *y) {
  if (cr->kind == PS_CRACK_SEGMENT) return segment_cuts(cr, x, y);
  /* 3D: the ends in a fixed order, so that the test is symmetric */
  int swap = 0;
  for (int k = 0; k < 3; k++)
    if (x[k] != y[k]) {
      swap = x[k] > y[k];
      break;
    }
  const double *a = swap ? y : x, *b = swap ? x : y;
  if (cr->kind == PS_CRACK_POLYGON) return polygon_cuts(cr, a, b);
  if (cr->kind == PS_CRACK_SPHERE) return sphere_cuts(cr, a, b);
  return 0;
}
