/* ess_model.c - forward ESS calibration model, its gradient and inverse. */
#include "ess_model.h"
#include "status.h"

#include <math.h>
#include <string.h>

#define COMP_MAX_ITER 50
#define COMP_TOL_RAD 1e-15

const char *const ess_param_names[ESS_NP] = {"a", "b", "c", "ks_deg", "kc_deg",
                                             "fit_install_y_arcsec", "fit_install_z_arcsec",
                                             "fit_sun_y_arcsec"};

void ess_model_init(ess_model *m, double theta0_rad, double roll_rad)
{
    memset(m, 0, sizeof *m);
    m->p[ESS_P_A] = 1.0;
    m->roll_rad = roll_rad;
    m->omega = 2.0 * M_PI / (theta0_rad / 4.0);
    ess_model_prepare(m);
}

void ess_model_prepare(ess_model *m)
{
    mat3 rx, ry, rz, dry, drz, t;
    rot_x(m->roll_rad, rx);
    rot_y(m->p[ESS_P_INST_Y], ry);
    rot_z(m->p[ESS_P_INST_Z], rz);
    drot_y(m->p[ESS_P_INST_Y], dry);
    drot_z(m->p[ESS_P_INST_Z], drz);
    mat3_mul(rx, ry, t);
    mat3_mul(t, rz, m->R);
    mat3_mul(t, drz, m->dR_z);
    mat3_mul(rx, dry, t);
    mat3_mul(t, rz, m->dR_y);
    double sx = m->sun_x_rad, sy = m->p[ESS_P_SUN_Y];
    sun_direction(sx, sy, m->v);
    m->dv[0] = -sin(sy) * sin(sx);
    m->dv[1] = cos(sy);
    m->dv[2] = -sin(sy) * cos(sx);
}

/* Partials of the structural + fine-code part at one point. */
typedef struct {
    double G;      /* d raw / d alpha_d */
    double dad_dT; /* d alpha_d / d T */
    double q, N, D;
    double sin_wa, cos_wa;
} structural_partials;

/* alpha_d = atan2(a T + b, c T + 1) and the raw output; partials if sp. */
static double structural(const ess_model *m, double T, structural_partials *sp)
{
    const double *p = m->p;
    double N = p[ESS_P_A] * T + p[ESS_P_B];
    double D = p[ESS_P_C] * T + 1.0;
    double ad = atan2(N, D);
    double sw = sin(m->omega * ad), cw = cos(m->omega * ad);
    double raw = ad - p[ESS_P_KS] * sw - p[ESS_P_KC] * cw;
    if (sp) {
        sp->q = N * N + D * D;
        sp->G = 1.0 - m->omega * (p[ESS_P_KS] * cw - p[ESS_P_KC] * sw);
        sp->dad_dT = (p[ESS_P_A] * D - N * p[ESS_P_C]) / sp->q;
        sp->N = N;
        sp->D = D;
        sp->sin_wa = sw;
        sp->cos_wa = cw;
    }
    return raw;
}

double ess_model_structural(const ess_model *m, double T)
{
    return structural(m, T, NULL);
}

/* Row i of matrix a times v. */
static inline double row_dot(const mat3 a, int i, const double v[3])
{
    return a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2];
}

void ess_turntable_matrix(double alpha_rad, double beta_rad, mat3 M)
{
    mat3 rx, ry;
    rot_x(alpha_rad, rx);
    rot_y(beta_rad, ry);
    mat3_mul(rx, ry, M);
}

double ess_model_predict(const ess_model *m, double alpha_rad, double beta_rad,
                         double grad[ESS_NP])
{
    mat3 M;
    ess_turntable_matrix(alpha_rad, beta_rad, M);
    return ess_model_predict_m(m, (const double(*)[3])M, grad);
}

double ess_model_predict_m(const ess_model *m, const mat3 M, double grad[ESS_NP])
{
    /* Only s_y and s_z are needed: T = s_y / s_z. */
    double w[3];
    mat3_vec(M, m->v, w);
    double sy = row_dot(m->R, 1, w), sz = row_dot(m->R, 2, w);
    double T = sy / sz;
    if (!grad)
        return structural(m, T, NULL);

    structural_partials sp;
    double raw = structural(m, T, &sp);
    grad[ESS_P_A] = sp.G * (sp.D / sp.q) * T;
    grad[ESS_P_B] = sp.G * (sp.D / sp.q);
    grad[ESS_P_C] = sp.G * (-sp.N / sp.q) * T;
    grad[ESS_P_KS] = -sp.sin_wa;
    grad[ESS_P_KC] = -sp.cos_wa;

    /* d raw / d s through T = s_y / s_z */
    double k = sp.G * sp.dad_dT;
    double g1 = k / sz, g2 = -k * sy / (sz * sz);
    grad[ESS_P_INST_Y] = g1 * row_dot(m->dR_y, 1, w) + g2 * row_dot(m->dR_y, 2, w);
    grad[ESS_P_INST_Z] = g1 * row_dot(m->dR_z, 1, w) + g2 * row_dot(m->dR_z, 2, w);
    double mdv[3];
    mat3_vec(M, m->dv, mdv);
    grad[ESS_P_SUN_Y] = g1 * row_dot(m->R, 1, mdv) + g2 * row_dot(m->R, 2, mdv);
    return raw;
}

int ess_model_compensate(const ess_model *m, double raw_rad, double *alpha_rad)
{
    const double *p = m->p;
    double ks = p[ESS_P_KS], kc = p[ESS_P_KC];
    if (m->omega * hypot(ks, kc) >= 1.0)
        return SUNMC_EDOM;
    double x = raw_rad;
    int converged = 0;
    for (int i = 0; i < COMP_MAX_ITER; i++) {
        double wa = m->omega * x;
        double f = x - ks * sin(wa) - kc * cos(wa) - raw_rad;
        double fp = 1.0 - m->omega * (ks * cos(wa) - kc * sin(wa));
        double dx = f / fp;
        x -= dx;
        if (fabs(dx) < COMP_TOL_RAD) {
            converged = 1;
            break;
        }
    }
    if (!converged)
        return SUNMC_EDOM;
    double td = tan(x);
    double den = p[ESS_P_C] * td - p[ESS_P_A];
    if (den == 0.0)
        return SUNMC_EDOM;
    *alpha_rad = atan((p[ESS_P_B] - td) / den);
    return SUNMC_OK;
}

void ess_model_kt(const ess_model *m, double *k_rad, double *t_rad)
{
    *k_rad = hypot(m->p[ESS_P_KS], m->p[ESS_P_KC]);
    *t_rad = atan2(m->p[ESS_P_KC], m->p[ESS_P_KS]);
}
