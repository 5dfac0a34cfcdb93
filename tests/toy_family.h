/* toy_family.h - a test-only sensor family, registered by the tests that
 * use it (sensor_family_register): proof that a family is a folder of its
 * own plus one registration, with nothing in core or cli naming it.
 *
 * The toy sensor reads one angle: reading = alpha (1 + scale) + offset +
 * bow alpha^2 + noise, alpha on a turntable from -span to +span.  The bow
 * (default 0) is the tolerance test_deviations_toy_tolerance adds "by one line plus
 * its physics" and follows into sampling, curve, budget and the lab
 * prediction.  Calibration fits the
 * straight line reading = p0 + p1 alpha by least squares; compensation
 * inverts it.  Noise-free, the fit is exact, so every number of a run has a
 * closed form.
 */
#ifndef SUNMC_TOY_FAMILY_H
#define SUNMC_TOY_FAMILY_H

#include "config.h"
#include "deviation.h"
#include "family.h"

/* The toy's deviation list: X(name, unit, count, stream, columns, default,
 * dist, max, help), as in ess_deviations.h. */
#define TOY_DEVIATIONS(X)                                                                         \
    X(scale_pct, "%", 1, 0, "scale_pct", "1", "uniform", 50, "scale-factor error")             \
    X(offset_arcsec, "arcsec", 1, 1, "offset_arcsec", "30", "uniform", 3600, "zero offset")   \
    X(bow_arcsec, "arcsec", 1, 2, "bow_arcsec", "0", "uniform", 3600,                          \
      "bow: reading error bow * alpha^2, alpha in rad")

typedef struct {
    TOY_DEVIATIONS(DEVIATION_X_TOLERANCE)
} toy_tolerances;

typedef struct {
    double span_deg;           /* [design] half range of alpha */
    toy_tolerances tol;
    double reading_arcsec;     /* [noise] sigma of a reading */
    double cal_step_deg;       /* [campaign] step of the turntable */
    double val_step_deg;       /* [validation] step of the validation grid */
} toy_config;

typedef struct {
    double scale_pct, offset_arcsec, bow_arcsec;
} toy_deviations;

#define toy_cfg(c) ((const toy_config *)(const void *)(c)->fam.bytes)

extern const sensor_family toy_family;

/* The reading (rad) of a unit with deviations d at alpha (rad), noise added. */
double toy_read_rad(const toy_deviations *d, double a_rad, double noise_arcsec);

/* The lab hooks (toy_lab.c). */
extern const struct family_lab toy_lab;

/* Unit `unit`'s deviations. */
void toy_sample(const sunmc_config *c, long unit, toy_deviations *d);

/* The campaign grid's size, and the one walk over each grid: alphas and
 * readings (rad), as `run` scores them and `simulate` writes them. */
long toy_cal_count(const sunmc_config *c);
void toy_campaign(const sunmc_config *c, const toy_deviations *d, long unit, double *a_rad,
                  double *y_rad);
void toy_validation(const sunmc_config *c, const toy_deviations *d, long unit, double *a_rad,
                    double *y_rad);

/* Least-squares line y = p[0] + p[1] a over n points with weights w (NULL: 1). */
void toy_line_fit(long n, const double *a, const double *y, const double *w, double p[2]);

/* The validation grid's alphas (deg): count, and value i. */
long toy_val_count(const sunmc_config *c);
double toy_val_alpha_deg(const sunmc_config *c, long i);

#endif
