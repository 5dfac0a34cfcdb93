/* ess_model.h - the ESS compensation model of the ESS paper (eq. 9, 12, 13)
 * inside the turntable calibration model (eq. 14, corrected), with analytic
 * derivatives and the exact inverse used for compensation.
 *
 * Forward model of the raw output for turntable angles (alpha, beta):
 *     s       = R_inst rot_x(alpha) rot_y(-beta) v_sun           (unit vector)
 *     R_inst  = rot_x(roll) rot_y(-inst_y) rot_z(inst_z)
 *     v_sun   = rot_y(-sun_x) rot_x(sun_y) (0, 0, 1)
 * (rotation.h's passive rotations; the table's beta, inst_y and sun_x turn
 * the sensor or the sun about Y the active way, hence their minus signs)
 *     T       = s_y / s_z                         = tan(incidence alpha)
 *     alpha_d = atan((a T + b) / (c T + d))       eq. 12 with d = 1
 *     raw     = alpha_d - ks sin(w alpha_d) - kc cos(w alpha_d)
 * with w = 2 pi / (theta0/4), so that eq. 9's k sin(4 pi alpha + t) (alpha in
 * degrees, theta0 = 2 deg) is k sin(w alpha + t) = ks sin + kc cos with
 * ks = k cos t, kc = k sin t.
 *
 * Fixed, not fitted (identifiability, see ess_calib.h): d = 1 (the common
 * scale of a, b, c, d), roll (a rotation inside eq. 12: fixed at its
 * measured value), sun_x (a beta offset: invisible to an alpha sensor).
 * The ESS paper writes R_rs after R(alpha, beta) in eq. 14; in that order
 * R_rs and V0 only enter as their product and cannot be calibrated.
 *
 * The extended model (calibration.model = extended, ess_model_ext.c)
 * replaces the fine-code term by the terms the physical sensor produces
 * (derivation in ess_model_ext.c; x = 2 pi alpha_d / theta0 is the
 * fine-code phase, c = cos alpha_d):
 *     raw = alpha_d - arg(1 + rho e^{4 i x}) / w1 - L(alpha_d),  w1 = 2 pi / theta0,
 *     rho = w1 [(ks + i kc) + (ks4 + i kc4) c^4 + (ks8 + i kc8) c^8],
 *     L   = k1s sin x + k1c cos x + (k2s + k2s2 c^2) sin 2x + (k2c + k2c2 c^2) cos 2x;
 * to first order in rho the arg term is the paper's ks sin 4x + kc cos 4x;
 * its second order is the 8th harmonic the third photocell harmonic makes
 * (ESS paper eq. 7 exactly, rather than eq. 9's first harmonic).
 */
#ifndef SUNMC_ESS_MODEL_H
#define SUNMC_ESS_MODEL_H

#include "lab_spline.h"
#include "lab_table.h"
#include "rotation.h"

#include <stddef.h>

enum ess_param {
    ESS_P_A = 0, /* eq. 12 a (d = 1): 1 + dH/H for a pure height error */
    ESS_P_B,     /* eq. 12 b: -dd/H for a pure offset */
    ESS_P_C,     /* eq. 12 c */
    ESS_P_KS,    /* fine-code term k cos t (rad) */
    ESS_P_KC,    /* fine-code term k sin t (rad) */
    ESS_P_INST_Y,/* installation rotation about Y (rad) */
    ESS_P_INST_Z,/* installation rotation about Z (rad) */
    ESS_P_SUN_Y, /* sun-simulator tilt toward Y (rad) */
    ESS_NP,      /* the paper's model: 8 parameters */
    /* the extended model's (rad): the 4x amplitude's incidence terms, the
     * fine period's fundamental and second harmonic */
    ESS_P_KS4 = ESS_NP, ESS_P_KC4, ESS_P_KS8, ESS_P_KC8, ESS_P_K1S, ESS_P_K1C, ESS_P_K2S,
    ESS_P_K2C, ESS_P_K2S2, ESS_P_K2C2,
    ESS_NP_EXT,  /* the extended model: 18 */
    ESS_NP_MAX = ESS_NP_EXT
};

/* calibration.model (the key's enum order). */
enum ess_model_kind { ESS_MODEL_PAPER = 0, ESS_MODEL_EXTENDED = 1, ESS_MODEL_SPLINE = 2,
                      ESS_MODEL_HYBRID = 3, ESS_MODEL_TABLE = 4 };
#define ESS_N_MODELS 5
/* Does model k fit core's spline (ess_spline.c)?  Its physics is then the
 * paper's: fitted under a hybrid's correction, nominal (not fitted, its
 * truth only) for spline and table; every physical function takes a kind
 * other than ESS_MODEL_EXTENDED as the paper's. */
#define ESS_MODEL_HAS_SPLINE(k) ((k) >= ESS_MODEL_SPLINE)

/* Every parameter's name (params.ini, calibrate's report), paper's first. */
extern const char *const ess_param_names[ESS_NP_MAX];

/* Parameters of a model of kind `kind`: ESS_NP or ESS_NP_EXT. */
int ess_model_np(int kind);

/* One term of the fine-code phase error a model fits: the harmonic n of the
 * fine period, times cos(alpha_d)^power, with the parameters of its sine
 * and cosine parts.  The alias detector checks each harmonic. */
typedef struct {
    int harmonic, power;
    int p_sin, p_cos;
} ess_fine_term;

/* The fine-code terms of a model kind; *n receives their count.  The
 * paper's single term comes first. */
const ess_fine_term *ess_model_fine_terms(int kind, int *n);

typedef struct {
    int kind;            /* enum ess_model_kind */
    int np;              /* ess_model_np(kind) */
    double p[ESS_NP_MAX];
    double roll_rad;     /* fixed installation roll about X */
    double sun_x_rad;    /* fixed sun tilt toward X */
    int sun_y_fixed;     /* 1: p[ESS_P_SUN_Y] is a measurement the fit kept (calibration.sun_y) */
    double omega;        /* 2 pi / fine-error period, 1/rad */
    /* derived by ess_model_prepare() */
    mat3 R, dR_y, dR_z;
    double v[3], dv[3];
    int invertible;      /* extended: ess_model_ext_invertible, for compensation */
    /* spline, table: the true angle as a function of the raw one (1-D);
     * hybrid: the paper model's error in it (ess_spline.c) */
    lab_spline spline;
    lab_table table;     /* table: the spline at its nodes */
} ess_model;

/* Identity model (a = 1, all else 0) for fine-code period theta0_rad: the
 * paper's, or of kind `kind`. */
void ess_model_init(ess_model *m, double theta0_rad, double roll_rad);
void ess_model_init_kind(ess_model *m, int kind, double theta0_rad, double roll_rad);

/* Recompute the rotation matrices after changing m->p; call before predict. */
void ess_model_prepare(ess_model *m);

/* The incidence-to-raw part: raw (rad) for sensor-frame incidence T = tan(alpha). */
double ess_model_structural(const ess_model *m, double T);

/* Predicted raw output (rad) at turntable angles (rad); grad (may be NULL)
 * receives d raw / d p[m->np]. */
double ess_model_predict(const ess_model *m, double alpha_rad, double beta_rad,
                         double grad[ESS_NP_MAX]);

/* The same from the turntable matrix M = rot_x(alpha) rot_y(-beta), which a
 * fit computes once per point (ess_turntable_matrix). */
double ess_model_predict_m(const ess_model *m, const mat3 M, double grad[ESS_NP_MAX]);
void ess_turntable_matrix(double alpha_rad, double beta_rad, mat3 M);

/* Turntable matrices rot_x(alpha) rot_y(-beta) of n points, structure of
 * arrays for the batch forms: m[3 r + c][i] = M_i[r][c].  Every array
 * holds vm_pad(n) values (vmath.h). */
typedef struct {
    size_t n;
    double *m[9];
} ess_table;

/* Fill t from alpha_rad, beta_rad (vm_pad(t->n) values each; pads 0). */
void ess_table_fill(ess_table *t, const double *alpha_rad, const double *beta_rad);

/* The fit's residuals and Jacobian at every point of t at once (vectorised):
 * f[i] = sw[i] (predicted - raw_rad[i]) and J[j ld + i] = sw[i] d pred / d
 * p_j, both 0 where sw[i] = 0 (a dropped point).  Arrays of vm_pad(t->n). */
void ess_model_batch(const ess_model *m, const ess_table *t, const double *raw_rad,
                     const double *sw, double *f, double *J, size_t ld);

/* Predicted raw output (rad) at every point of t into raw_rad[vm_pad(n)]. */
void ess_model_predict_batch(const ess_model *m, const ess_table *t, double *raw_rad);

/* Compensation, the exact inverse of the model: solve
 * alpha_d - ks sin(w alpha_d) - kc cos(w alpha_d) = raw by Halley's method
 * (bisection where it does not settle; the extended model: its fine-code
 * terms, by Newton), then
 * eq. 13: tan(alpha) = (b - d tan alpha_d) / (c tan alpha_d - a).
 * SUNMC_EDOM when the fine-code term is not invertible (w k >= 1; the
 * extended model: ess_model_ext_invertible) or the iteration fails. */
int ess_model_compensate(const ess_model *m, double raw_rad, double *alpha_rad);

/* The same for n raws at once (vectorised; each gives the bits it gives
 * alone): alpha_rad[i], status[i] = SUNMC_OK or SUNMC_EDOM.  Returns
 * SUNMC_EDOM if any reading failed. */
#define ESS_COMP_CHUNK 64
int ess_model_compensate_batch(const ess_model *m, size_t n, const double *raw_rad,
                               double *alpha_rad, int *status);
/* The same by m's physics alone (a hybrid's without its correction). */
int ess_model_phys_compensate_batch(const ess_model *m, size_t n, const double *raw_rad,
                                    double *alpha_rad, int *status);

/* ess_model_compensate_batch of n raws and of raw0, the same readings
 * without their noise: the paper model starts each raw0's iteration from
 * its raw's solution moved by (raw0 - raw) / g' (a step or two instead of
 * four), to the same tolerance (the bits may differ from raw0 alone in
 * the last place).  Returns SUNMC_EDOM if any reading of either failed. */
int ess_model_compensate_pair_batch(const ess_model *m, size_t n, const double *raw_rad,
                                    const double *raw0_rad, double *alpha_rad,
                                    double *alpha0_rad, int *status, int *status0);

/* ---- spline, table and hybrid (ess_spline.c) ----
 * spline: core's penalised B-spline (lab_spline.h) of the true angle (the
 * model's truth: eq. 14 with the roll and sun tilt as measured) over the
 * raw one, one input (the sensor reads one axis); table: core's look-up
 * table of the same (lab_table.h), the spline at its nodes; hybrid: the
 * paper's model fitted first, and a spline of its error over the raw
 * angle, zero where the physics is exact.  Its compensation: SUNMC_EDOM
 * for a raw angle outside the calibrated field (not extrapolated). */
int ess_spline_compensate_batch(const ess_model *m, size_t n, const double *raw_rad,
                                double *alpha_rad, int *status);
/* The true angle m assigns to turntable angles (alpha, beta) (rad). */
double ess_model_truth(const ess_model *m, double alpha_rad, double beta_rad);

/* Paper-style k (rad, >= 0) and t (rad) from ks, kc. */
void ess_model_kt(const ess_model *m, double *k_rad, double *t_rad);

/* ---- the extended model's fine-code terms (ess_model_ext.c) ---- */

/* F(alpha_d) = alpha_d - raw of the extended model at alpha_d (rad), its
 * derivative dF/dalpha_d and dF/dp_j of the fine-code parameters (j = KS,
 * KC and ESS_P_KS4..ESS_P_K2C2; the others 0) into dF_dp[ESS_NP_MAX]
 * (NULL: not wanted). */
double ess_model_ext_fine(const ess_model *m, double ad_rad, double *dF_dad,
                          double dF_dp[ESS_NP_MAX]);

/* 1 when the extended model's fine-code terms keep the output monotonic
 * (an upper bound on dF/dalpha_d below 1 everywhere), so compensation has
 * a unique inverse; *bound receives the bound.  With rho constant the
 * bound is exact: 4 |rho| / (1 + |rho|) < 1, |rho| < 1/3 (the paper's
 * first-order term needs w k < 1, |rho| < 1/4). */
int ess_model_ext_invertible(const ess_model *m, double *bound);

/* The extended model's ess_model_predict_m. */
double ess_model_ext_predict_m(const ess_model *m, const mat3 M, double grad[ESS_NP_MAX]);

/* The extended model's batch forms (same contracts as ess_model_batch,
 * ess_model_predict_batch and ess_model_compensate_batch's chunks). */
void ess_model_ext_batch(const ess_model *m, const ess_table *t, const double *raw_rad,
                         const double *sw, double *f, double *J, size_t ld);
void ess_model_ext_predict_batch(const ess_model *m, const ess_table *t, double *raw_rad);
void ess_model_ext_compensate_chunk(const ess_model *m, size_t k, const double *raw,
                                    double *alpha, int *status);

#endif
