/* ess_sensor.h - the physical encoded sun sensor (ESS): what one built unit
 * outputs for a sun direction.  This generates the data; the compensation
 * model of ess_model.h only fits them.
 *
 * Frames: sensor X across the code rows, Y along them (the sensing
 * direction), Z the boresight.  s is the unit vector toward the sun in the
 * sensor frame; incident angle alpha = atan2(s_y, s_z), incoming angle
 * beta = asin(s_x).
 *
 * Geometry (ess_slit.c): the entrance slit lies at height H + dH over the
 * code dial, offset dd along Y and tilted dphi about Z; the dial is tilted
 * tau (dial_tilt_deg) about the code-row axis Y, so the row at x sits at
 * height h(x) = H + dH + x tan(tau) under the slit.  The slit image
 * crosses the row at x = x_r at the dial coordinate
 *     eta(x_r) = h tan(alpha) - dd - (x_r + h s_x/s_z) tan(dphi),
 * and every row is etched by the rule eta = H tan(angle), so a row reads the
 * angle atan(eta/H).  dH alone gives alpha' = atan((H+dH)/H tan alpha).
 *
 * Coarse code (ess_coarse.c): Gray-coded rows of cells coarse_resolution
 * wide, each bit read at its own row position.
 *
 * Fine code (ess_finecode.c): 4 rows of period theta0 in quarter-period
 * steps; row m's current is the Fourier series of ESS paper eq. 2 with the
 * row's gain and etching error, harmonics derived from slit width, dial duty
 * and the sun's disc (or given), scaled by the illumination cos(incidence).
 * The four currents are demodulated by the four-quadrant chopper of Fig. 8:
 * the phase of the fundamental (DFT bin 1) of the chopped sequence.
 */
#ifndef SUNMC_ESS_SENSOR_H
#define SUNMC_ESS_SENSOR_H

#include "deviation.h"
#include "ess_config.h"
#include "rng.h"

#define ESS_MAX_COARSE_ROWS CONFIG_LIST_MAX
#define ESS_HARMONICS 3 /* odd harmonics 1, 3, 5 */

/* The sampled deviations of one unit, in the units of their names: one
 * field per line of ESS_DEVIATIONS (ess_deviations.h), then the derived roll
 * measurement. */
typedef struct {
    double dH_um, dd_um, dphi_deg, slit_width_um, harmonic_phase_deg;
    double gain_pct[ESS_FINE_ROWS];
    double etch_um[ESS_FINE_ROWS];
    double install_x_arcsec, install_y_arcsec, install_z_arcsec;
    double sun_x_arcsec, sun_y_arcsec;
    double spacer_cte_ppm_k, mask_cte_ppm_k; /* the unit's CTEs against the environment's */
    double dial_tilt_deg; /* the dial's tilt about the code-row axis */
    double roll_measured_arcsec; /* the alignment measurement of install_x */
} ess_deviations;

/* Columns of a unit's deviations: the list's, then roll_measured_arcsec. */
#define ESS_N_DEV (ESS_N_TOL_COLUMNS + 1)

/* ESS_DEVIATIONS as a table (ess_sensor.c). */
extern const deviation_spec ess_deviation_list[ESS_N_TOL];

/* Column names (with units) of the deviations, in the order of
 * ess_deviations_values(). */
extern const char *const ess_deviation_names[ESS_N_DEV];
void ess_deviations_values(const ess_deviations *d, double out[ESS_N_DEV]);

/* Draw unit `unit`'s deviations: each tolerance from its own stream (its
 * stream id in ESS_DEVIATIONS), so it depends only on (seed, unit, id); the
 * roll measurement from RNG_STREAM_ALIGNMENT. */
void ess_deviations_sample(const sunmc_config *c, uint64_t seed, long unit, ess_deviations *d);

/* calibration.sun_y = measured: unit `unit`'s measurement of its sun
 * simulator's tilt toward Y (d->sun_y_arcsec plus a normal error of
 * calibration.sun_y_sigma_arcsec from stream RNG_STREAM_SUN_Y, drawn only
 * here, so no other draw moves); 0 when the tilt is fitted. */
double ess_sun_y_measured_arcsec(const sunmc_config *c, uint64_t seed, long unit,
                                 const ess_deviations *d);

/* The fine rows' shortcut's range (fine_by_series): the dial tangents'
 * differences, and the phase turn they make (ess_lane.h's series are
 * exact to double precision within these). */
#define ESS_FINE_SERIES_TAN 1e-2
#define ESS_FINE_SERIES_PHASE 0.25
/* The noise-free phase from the noisy one (phase0_by_series): the largest
 * tangent of the angle between the two phasors the series takes. */
#define ESS_PHASE0_SERIES_TAN 0.25

/* The most coarse cells (2^rows) whose edge tangents a sensor tabulates
 * (coarse_by_table): 8 rows, 6 KiB a sensor. */
#define ESS_COARSE_TABLE_CELLS 256

/* One built sensor, ready to read: lengths in mm, angles in radians. */
typedef struct {
    double H_mm;        /* design height: the etching rule */
    double Hr_mm;       /* actual height H + dH */
    double dd_mm;
    double tan_dphi;
    /* The dial's tilt about the code-row axis: row x (from the pivot, as
     * below) sits at height Hp_mm + x tan_tau, Hp_mm = Hr + pivot tan_tau
     * (the axis is the dial's centre line x = 0). */
    double tan_tau;
    double Hp_mm;
    double theta0_rad;
    double coarse_res_rad;
    int n_coarse;
    double coarse_cells;      /* 2^n_coarse */
    double coarse_origin_rad; /* lower edge of cell 0: -cells/2 x resolution */
    /* Row positions across the rows, measured from the slit's tilt pivot
     * (design.tilt_pivot_mm): the lever arm of dphi. */
    double coarse_x_mm[ESS_MAX_COARSE_ROWS];
    /* 1 when every coarse row's dial tangent lies within half a cell of
     * fine row 0's (tilt and etching small): the batch then reads each
     * coarse row by comparing its tangent with the tangents of the two
     * edges of fine row 0's cell instead of an arctangent (ess_sensor.c) */
    int coarse_by_compare;
    double coarse_tan_res; /* tan(coarse_res_rad) */
    /* 1 when the dial has at most ESS_COARSE_TABLE_CELLS cells: the
     * comparison path then takes each cell's edge tangents from the
     * tables below (made once by ess_sensor_init, the same bits as a
     * reading made them) and reads only the two outermost coarse rows,
     * plus the one row that tells two neighbouring cells apart where
     * those two differ (ess_sensor.c) */
    int coarse_by_table;
    int coarse_row_min, coarse_row_max; /* the rows of least and greatest x */
    /* per cell k: the tangents of its lower and upper edge (-inf, +inf
     * at the dial's ends), and the x of the row whose Gray bit differs
     * between cells k and k + 1 */
    double coarse_lo_tan[ESS_COARSE_TABLE_CELLS];
    double coarse_hi_tan[ESS_COARSE_TABLE_CELLS];
    double coarse_step_x_mm[ESS_COARSE_TABLE_CELLS];
    double fine_x_mm[ESS_FINE_ROWS];
    double gain[ESS_FINE_ROWS];       /* 1 + gain error */
    double etch_mm[ESS_FINE_ROWS];    /* etching position error */
    /* Fine row m's dial tangent less row 0's, the same for every sun
     * direction: -((x_m - x_0) tan(dphi) + etch_m - etch_0) / H. */
    double fine_dt[ESS_FINE_ROWS];
    /* The dial tilt's share of it, per unit w = s_y/s_z - s_x/s_z tan(dphi):
     * (x_m - x_0) tan(tau) / H (row m's tangent is fine_dt + fine_dt_w w). */
    double fine_dt_w[ESS_FINE_ROWS];
    /* The largest |w| for which the shortcuts below hold (fine_by_series,
     * coarse_by_compare: the dial tilt's row differences grow with w);
     * +inf without a dial tilt.  A reading beyond it is made by the
     * arctangent paths (ess_sensor_output_chunk). */
    double w_safe;
    /* 1 when every |fine_dt| <= ESS_FINE_SERIES_TAN and 2 pi / theta0
     * times it <= ESS_FINE_SERIES_PHASE: the batch then makes rows 1-3's
     * currents from row 0's arctangent, cosine and sine by series
     * (ess_lane_current_from0) instead of their own (ess_sensor.c) */
    int fine_by_series;
    double fine_turn; /* 2 pi / theta0: phase per radian of dial angle */
    /* The series path's constants (ess_lane_harmonics_q,
     * ess_lane_combine_s): 1 / H, theta0 / (2 pi) and 1 / theta0, the
     * slit's sinc argument per unit cos^2(psi), w / (H theta0), and the
     * harmonics' scales dial_sun[n] / norm1 and dial_sun[n] / (n norm1)
     * (n = 1, 3, 5), so that a reading divides once, not nine times. */
    double inv_H;
    double period_per_turn, inv_theta0; /* theta0 / (2 pi), 1 / theta0 */
    double slit_z_per_cos2;
    double harm_scale[ESS_HARMONICS], harm_scale_n[ESS_HARMONICS];
    /* 1 (ess_sensor_init): the series path's noise-free phase is the noisy
     * one turned by the arctangent of the noise's small angle (series,
     * ess_lane_atan_quarter) instead of its own atan2, per lane while that
     * tangent is within ESS_PHASE0_SERIES_TAN; 0: atan2 (tests) */
    int phase0_by_series;
    int harmonics_given;
    double given_ratio[ESS_HARMONICS];/* 1, a3/a1, a5/a1 when given */
    double slit_width_mm;             /* actual slit width */
    double duty;
    double sun_diameter_rad;
    double harmonic_phase_rad;        /* phase of the 3rd harmonic */
    double harmonic_cos, harmonic_sin;/* its cosine and sine */
    double dial_sun[ESS_HARMONICS];   /* dial x sun-disc transfer of n = 1, 3, 5 */
    double dc_ratio;                  /* DC / a1 of the fine-row currents */
    double norm1;                     /* fundamental transfer at normal incidence */
} ess_sensor;

/* Build the sensor from its design and deviations. */
void ess_sensor_init(ess_sensor *s, const ess_design *d, const ess_deviations *dev);

/* Dial coordinate (mm) where the slit image crosses the row at x_mm, for a
 * sun vector with s_x/s_z = u and s_y/s_z = v (ess_slit.c). */
double ess_slit_eta_mm(const ess_sensor *s, double x_mm, double u, double v);

/* Relative amplitudes c_n (n = 1, 3, 5) of the fine-row currents at dial
 * angle psi (radians), normalised to the fundamental at normal incidence
 * (ess_finecode.c). */
void ess_finecode_harmonics(const ess_sensor *s, double psi_rad, double c[ESS_HARMONICS]);

/* Precompute the fine-code constants (dial_sun, norm1, dc_ratio) from the
 * sensor's duty, sun diameter, slit width and period. */
void ess_finecode_init(ess_sensor *s);

/* Fine-code phase in [0, 2 pi) demodulated from the four row currents
 * (ESS paper Fig. 8): atan2(I4 - I2, I3 - I1) with rows numbered 1..4. */
double ess_finecode_demodulate(const double current[ESS_FINE_ROWS]);

/* The four row currents (units of a1 at normal incidence) for row readings
 * psi_rad[m] (dial angle at each fine row), illumination factor `illum`
 * and additive noise[m] (NULL for none). */
void ess_finecode_currents(const ess_sensor *s, const double psi_rad[ESS_FINE_ROWS], double illum,
                           const double noise[ESS_FINE_ROWS], double current[ESS_FINE_ROWS]);

/* Coarse estimate (radians, cell centre) from the Gray rows at their
 * readings psi_rad[j] (ess_coarse.c). */
double ess_coarse_read(const ess_sensor *s, const double psi_rad[]);

/* Combine coarse estimate and fine phase into the output angle (radians):
 * the fine period nearest the coarse estimate. */
double ess_combine(double coarse_rad, double fine_phase, double theta0_rad);

/* Readings per vectorised chunk (ess_sensor_output_chunk). */
#define ESS_CHUNK 64

/* The raw outputs of k <= ESS_CHUNK readings at once: sun vectors (sx, sy,
 * sz)[i] and row noises noise[m][i] (arrays of vm_pad(k) values, aligned to
 * VM_ALIGN, pads filled with any valid values: vmath.h) into out_rad[i],
 * the same readings without the noise into out0_rad[i] (NULL: not wanted;
 * the bits of a call with zero noise), status[i] = SUNMC_OK or SUNMC_EDOM
 * (sun behind or grazing; out_rad[i] is then meaningless).  SUNMC_EINPUT if
 * k > ESS_CHUNK.  A reading gives the same bits in any lane of any chunk. */
int ess_sensor_output_chunk(const ess_sensor *s, size_t k, const double *sx, const double *sy,
                            const double *sz, const double *const noise[ESS_FINE_ROWS],
                            double *out_rad, double *out0_rad, int *status);

/* Raw output angle (radians) for sun vector sv (unit, toward the sun, s_z >
 * 0).  row_noise (NULL = noiseless) is the additive noise of the 4 fine-row
 * currents in units of a1 at normal incidence.  Returns SUNMC_EDOM when the
 * sun is behind or at grazing incidence. */
int ess_sensor_output(const ess_sensor *s, const double sv[3], const double row_noise[ESS_FINE_ROWS],
                      double *out_rad);

#endif
