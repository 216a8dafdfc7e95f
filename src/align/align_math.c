/*
 * align_math.c: the small dense linear algebra the alignment needs, kept private to
 * it (align_internal.h): cyclic Jacobi eigen-decomposition of symmetric matrices up to
 * 8 x 8 (surface covariance 3 x 3, normal-line moment matrices), Cholesky solves of the
 * Gauss-Newton normal equations (at most 5 unknowns), and orthonormal frames.
 * Sizes are tiny and fixed, so plain loops on stack arrays are the clearest choice.
 */
#include "align/align_internal.h"

#include <string.h>

void al_eig_sym(int n, const double *a, double *w, double *v)
{
    double m[64], vv[64];
    memcpy(m, a, (size_t)(n * n) * sizeof(double));
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            vv[i * n + j] = i == j;
    for (int sweep = 0; sweep < 60; sweep++) {
        double off = 0, diag = 0;
        for (int i = 0; i < n; i++) {
            diag += m[i * n + i] * m[i * n + i];
            for (int j = i + 1; j < n; j++)
                off += m[i * n + j] * m[i * n + j];
        }
        if (off <= 1e-30 * (diag + 1e-300))
            break;
        for (int p = 0; p < n; p++) {
            for (int q = p + 1; q < n; q++) {
                double apq = m[p * n + q];
                if (apq == 0)
                    continue;
                double theta = (m[q * n + q] - m[p * n + p]) / (2 * apq);
                double t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1));
                double c = 1 / sqrt(t * t + 1), s = t * c;
                for (int k = 0; k < n; k++) {
                    double mkp = m[k * n + p], mkq = m[k * n + q];
                    m[k * n + p] = c * mkp - s * mkq;
                    m[k * n + q] = s * mkp + c * mkq;
                }
                for (int k = 0; k < n; k++) {
                    double mpk = m[p * n + k], mqk = m[q * n + k];
                    m[p * n + k] = c * mpk - s * mqk;
                    m[q * n + k] = s * mpk + c * mqk;
                }
                for (int k = 0; k < n; k++) {
                    double vkp = vv[k * n + p], vkq = vv[k * n + q];
                    vv[k * n + p] = c * vkp - s * vkq;
                    vv[k * n + q] = s * vkp + c * vkq;
                }
            }
        }
    }
    /* sort ascending (selection sort on at most 8 entries) */
    int order[8];
    for (int i = 0; i < n; i++)
        order[i] = i;
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++)
            if (m[order[j] * n + order[j]] < m[order[i] * n + order[i]]) {
                int t = order[i];
                order[i] = order[j];
                order[j] = t;
            }
    for (int k = 0; k < n; k++) {
        w[k] = m[order[k] * n + order[k]];
        for (int i = 0; i < n; i++)
            v[i * n + k] = vv[i * n + order[k]];
    }
}

bool al_solve_spd(int n, const double *a, const double *b, double *x)
{
    double l[64], y[8];
    for (int i = 0; i < n; i++) {
        for (int j = 0; j <= i; j++) {
            double s = a[i * n + j];
            for (int k = 0; k < j; k++)
                s -= l[i * n + k] * l[j * n + k];
            if (i == j) {
                if (!(s > 0))
                    return false;
                l[i * n + i] = sqrt(s);
            } else {
                l[i * n + j] = s / l[j * n + j];
            }
        }
    }
    for (int i = 0; i < n; i++) {
        double s = b[i];
        for (int k = 0; k < i; k++)
            s -= l[i * n + k] * y[k];
        y[i] = s / l[i * n + i];
    }
    for (int i = n - 1; i >= 0; i--) {
        double s = y[i];
        for (int k = i + 1; k < n; k++)
            s -= l[k * n + i] * x[k];
        x[i] = s / l[i * n + i];
    }
    return true;
}

void al_perp_frame(const double d[3], double u[3], double v[3])
{
    /* start from the coordinate axis least aligned with d */
    double e[3] = {0, 0, 0};
    int k = 0;
    if (fabs(d[1]) < fabs(d[k]))
        k = 1;
    if (fabs(d[2]) < fabs(d[k]))
        k = 2;
    e[k] = 1;
    v3_cross(d, e, u);
    v3_normalize(u);
    v3_cross(d, u, v);
    /* (u, v, d) right-handed: u x v = d */
    double chk[3];
    v3_cross(u, v, chk);
    if (v3_dot(chk, d) < 0) {
        v[0] = -v[0];
        v[1] = -v[1];
        v[2] = -v[2];
    }
}

void al_rot_axis(const double k[3], double ang, double r[9])
{
    double c = cos(ang), s = sin(ang), t = 1 - c;
    double x = k[0], y = k[1], z = k[2];
    r[0] = t * x * x + c;
    r[1] = t * x * y - s * z;
    r[2] = t * x * z + s * y;
    r[3] = t * x * y + s * z;
    r[4] = t * y * y + c;
    r[5] = t * y * z - s * x;
    r[6] = t * x * z - s * y;
    r[7] = t * y * z + s * x;
    r[8] = t * z * z + c;
}
