/* cmd_simulate.c - `sunmc simulate`: one simulated unit's calibration
 * campaign as a lab records it, with the truth behind it. */
#include "ess_simulate.h"
#include "dss_simulate.h"
#include "dss_unit.h"
#include "ess_unit.h"
#include "family.h"
#include "cli.h"
#include "output.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char simulate_help[] =
    "usage: sunmc simulate CONFIG --unit U --out DIR [--seed S] [--set SECTION.KEY=VALUE]...\n"
    "Writes unit U's turntable calibration campaign exactly as `sunmc run` simulates it (same\n"
    "seed, same noise), in the lab's CSV format, so it can be calibrated with `sunmc calibrate`:\n"
    "  DIR/campaign.csv    alpha_deg,beta_deg,output_deg,weight (weight 0: a reading the lab\n"
    "                      drops: off the table angle by more than half a fine period)\n"
    "  DIR/truth.csv       per campaign row: the table's true angles (encoder error), the true\n"
    "                      incidence; the unit's deviations as '#' comments\n"
    "  DIR/validation.csv  the readings `run` validates the unit on: alpha_deg,beta_deg,\n"
    "                      output_deg,truth_deg (compensate it and compare with truth_deg)\n"
    "Prints the unit's measured installation roll, to pass to calibrate with\n"
    "--set calibration.roll_measured_arcsec=VALUE.\n"
    "For a DSS config: campaign.csv b1_deg,b2_deg,x_px,y_px,weight; truth.csv; validation.csv\n"
    "b1_deg,b2_deg,x_px,y_px,truth_alpha_deg,truth_beta_deg (the readings `run` validates on).\n";

typedef struct {
    size_t n;
    double *a_true, *b_true, *inc, *raw;
    int *seen;
    size_t nv;
    double *va, *vb, *vraw, *vtruth;
    int *vstatus;
} sim_buffers;

static void sim_free(sim_buffers *b)
{
    free(b->a_true);
    free(b->b_true);
    free(b->inc);
    free(b->raw);
    free(b->seen);
    free(b->va);
    free(b->vb);
    free(b->vraw);
    free(b->vtruth);
    free(b->vstatus);
}

static int sim_alloc(sim_buffers *b, size_t n, size_t nv)
{
    memset(b, 0, sizeof *b);
    b->n = n;
    b->nv = nv;
    b->a_true = malloc(n * sizeof(double));
    b->b_true = malloc(n * sizeof(double));
    b->inc = malloc(n * sizeof(double));
    b->raw = malloc(n * sizeof(double));
    b->seen = malloc(n * sizeof(int));
    b->va = malloc((nv + 1) * sizeof(double));
    b->vb = malloc((nv + 1) * sizeof(double));
    b->vraw = malloc((nv + 1) * sizeof(double));
    b->vtruth = malloc((nv + 1) * sizeof(double));
    b->vstatus = malloc((nv + 1) * sizeof(int));
    return b->a_true && b->b_true && b->inc && b->raw && b->seen && b->va && b->vb && b->vraw &&
           b->vtruth && b->vstatus;
}

static int simulate_ess(const cli_options *o, const sunmc_config *c)
{
    const ess_config *ec = ess_cfg(c);
    ess_deviations dev;
    ess_unit u;
    ess_deviations_sample(c, (uint64_t)c->seed, o->unit, &dev);
    ess_unit_build(c, &dev, &u);
    size_t n = ess_campaign_size(c), nv = ess_validation_size(c);
    ess_calib_workspace *cw = n > ESS_NP ? ess_calib_alloc(n) : NULL;
    sim_buffers b;
    if (n <= ESS_NP) {
        fprintf(stderr, "sunmc simulate: the campaign has %zu points, the ess model %d "
                        "parameters\n", n, ESS_NP);
        return EXIT_BAD_INPUT;
    }
    if (!cw || !sim_alloc(&b, n, nv)) {
        if (cw)
            sim_free(&b);
        ess_calib_free(cw);
        fprintf(stderr, "sunmc simulate: out of memory\n");
        return 1;
    }
    int gross;
    ess_unit_campaign(c, &u, o->unit, cw, &gross);
    ess_campaign_truth(c, &u, o->unit, b.a_true, b.b_true, b.inc, b.raw, b.seen);
    ess_validation_readings(c, &u, o->unit, b.va, b.vb, b.vraw, b.vtruth, b.vstatus);
    for (size_t i = 0; i < n; i++)
        if (b.raw[i] != cw->raw_rad[i]) {
            fprintf(stderr, "sunmc simulate: internal error: the truth replay differs from the "
                            "campaign at row %zu\n", i);
            sim_free(&b);
            ess_calib_free(cw);
            return 1;
        }

    char err[SUNMC_ERRLEN];
    out_set os;
    FILE *fc = NULL, *ft = NULL, *fv = NULL;
    int st = out_begin(&os, o->out, err, sizeof err);
    if (st == SUNMC_OK)
        st = out_open(&os, "campaign.csv", &fc, err, sizeof err);
    if (st == SUNMC_OK)
        st = out_open(&os, "truth.csv", &ft, err, sizeof err);
    if (st == SUNMC_OK)
        st = out_open(&os, "validation.csv", &fv, err, sizeof err);
    long n_val = 0, n_val_gross = 0, n_val_unseen = 0;
    if (st == SUNMC_OK) {
        double roll = dev.roll_measured_arcsec;
        fprintf(fc, "# sunmc %s simulate: unit %ld of %s (%s), seed %ld\n", SUNMC_VERSION,
                o->unit, o->config, c->product, c->seed);
        fprintf(fc, "# measured installation roll: calibration.roll_measured_arcsec = %.17g\n",
                roll);
        fprintf(fc, "alpha_deg,beta_deg,output_deg,weight\n");
        fprintf(ft, "# sunmc %s simulate: truth of unit %ld of %s, seed %ld\n", SUNMC_VERSION,
                o->unit, o->config, c->seed);
        double dv[ESS_N_DEV];
        ess_deviations_values(&dev, dv);
        for (int i = 0; i < ESS_N_DEV; i++)
            fprintf(ft, "# %s = %.17g\n", ess_deviation_names[i], dv[i]);
        fprintf(ft, "alpha_deg,beta_deg,alpha_true_deg,beta_true_deg,incidence_deg,output_deg,"
                    "seen\n");
        long na =
            grid_count(ec->cal_alpha_min_deg, ec->cal_alpha_max_deg, ec->cal_alpha_step_deg, 0);
        for (size_t i = 0; i < n; i++) {
            /* The recorded angles as the campaign computes them, so that
             * reading them back gives the very same radians. */
            double a_deg = ec->cal_alpha_min_deg + (double)((long)i % na) * ec->cal_alpha_step_deg;
            double b_deg = ec->cal_beta_deg.v[(long)i / na];
            fprintf(fc, "%.17g,%.17g,%.17g,%g\n", a_deg, b_deg, cw->raw_rad[i] * DEG_PER_RAD,
                    cw->weight[i]);
            fprintf(ft, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d\n", a_deg, b_deg,
                    b.a_true[i] * DEG_PER_RAD, b.b_true[i] * DEG_PER_RAD, b.inc[i] * DEG_PER_RAD,
                    cw->raw_rad[i] * DEG_PER_RAD, b.seen[i]);
        }
        for (size_t i = 0; i < nv; i++) {
            n_val_unseen += b.vstatus[i] == ESS_READING_UNSEEN;
            n_val_gross += b.vstatus[i] == ESS_READING_GROSS;
        }
        fprintf(fv, "# sunmc %s simulate: validation readings of unit %ld of %s, seed %ld;\n"
                    "# %ld readings off the truth by more than half a fine period and %ld with "
                    "the sun unseen are left out, as in `run`\n",
                SUNMC_VERSION, o->unit, o->config, c->seed, n_val_gross, n_val_unseen);
        fprintf(fv, "alpha_deg,beta_deg,output_deg,truth_deg\n");
        for (size_t i = 0; i < nv; i++)
            if (b.vstatus[i] == ESS_READING_OK) {
                fprintf(fv, "%.17g,%.17g,%.17g,%.17g\n", b.va[i] * DEG_PER_RAD,
                        b.vb[i] * DEG_PER_RAD, b.vraw[i] * DEG_PER_RAD,
                        b.vtruth[i] * DEG_PER_RAD);
                n_val++;
            }
        st = out_commit(&os, err, sizeof err);
    } else {
        out_abort(&os);
    }
    if (st == SUNMC_OK) {
        printf("unit %ld of %s (seed %ld): %zu campaign points (%d dropped as gross errors), "
               "%ld validation readings\n",
               o->unit, c->product, c->seed, n, gross, n_val);
        printf("wrote %s/campaign.csv, %s/truth.csv, %s/validation.csv\n", o->out, o->out, o->out);
        printf("calibrate with the unit's measured roll:\n"
               "  sunmc calibrate --sensor ess --config %s --set "
               "calibration.roll_measured_arcsec=%.17g %s/campaign.csv --out DIR\n",
               o->config, dev.roll_measured_arcsec, o->out);
    } else {
        fprintf(stderr, "sunmc simulate: %s\n", err);
    }
    sim_free(&b);
    ess_calib_free(cw);
    return cli_exit_code(st);
}

static int simulate_dss(const cli_options *o, const sunmc_config *c)
{
    const dss_config *dc = dss_cfg(c);
    dss_deviations dev;
    dss_unit u;
    dss_deviations_sample(c, (uint64_t)c->seed, o->unit, &dev);
    dss_unit_build(c, &dev, &u);
    size_t n = dss_campaign_size(c), nv = dss_validation_size(c);
    double *v[7], *w[6];
    int ok = 1, *wseen = malloc((nv + 1) * sizeof(int));
    ok &= wseen != NULL;
    for (int k = 0; k < 7; k++)
        ok &= (v[k] = malloc((n + 1) * sizeof(double))) != NULL;
    for (int k = 0; k < 6; k++)
        ok &= (w[k] = malloc((nv + 1) * sizeof(double))) != NULL;
    if (!ok) {
        for (int k = 0; k < 7; k++)
            free(v[k]);
        for (int k = 0; k < 6; k++)
            free(w[k]);
        free(wseen);
        fprintf(stderr, "sunmc simulate: out of memory\n");
        return 1;
    }
    size_t seen = dss_unit_campaign(c, &u, o->unit, v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
    dss_validation_readings(c, &u, o->unit, w[0], w[1], w[2], w[3], w[4], w[5], wseen);
    char err[SUNMC_ERRLEN];
    out_set os;
    FILE *fc = NULL, *ft = NULL, *fv = NULL;
    long n_val = 0;
    int st = out_begin(&os, o->out, err, sizeof err);
    if (st == SUNMC_OK)
        st = out_open(&os, "campaign.csv", &fc, err, sizeof err);
    if (st == SUNMC_OK)
        st = out_open(&os, "truth.csv", &ft, err, sizeof err);
    if (st == SUNMC_OK)
        st = out_open(&os, "validation.csv", &fv, err, sizeof err);
    if (st == SUNMC_OK) {
        long nb = grid_count(dc->cal_b_min_deg, dc->cal_b_max_deg, dc->cal_b_step_deg, 0);
        fprintf(fc, "# sunmc %s simulate: unit %ld of %s (%s), seed %ld; weight 0: no spot\n",
                SUNMC_VERSION, o->unit, o->config, c->product, c->seed);
        fprintf(fc, "b1_deg,b2_deg,x_px,y_px,weight\n");
        fprintf(ft, "# sunmc %s simulate: truth of unit %ld of %s, seed %ld\n", SUNMC_VERSION,
                o->unit, o->config, c->seed);
        double dv[DSS_N_DEV];
        dss_deviations_values(&dev, dv);
        for (int i = 0; i < DSS_N_DEV; i++)
            fprintf(ft, "# %s = %.17g\n", dss_deviation_names[i], dv[i]);
        fprintf(ft, "b1_deg,b2_deg,truth_alpha_deg,truth_beta_deg,seen\n");
        for (size_t i = 0; i < n; i++) {
            /* b1 varies slowest; the degrees as the campaign computes them. */
            double b1 = dc->cal_b_min_deg + (double)((long)i / nb) * dc->cal_b_step_deg;
            double b2 = dc->cal_b_min_deg + (double)((long)i % nb) * dc->cal_b_step_deg;
            int spot = v[4][i] > 0 && isfinite(v[2][i]) && isfinite(v[3][i]);
            fprintf(fc, "%.17g,%.17g,%.17g,%.17g,%g\n", b1, b2, spot ? v[2][i] : 0.0,
                    spot ? v[3][i] : 0.0, spot ? v[4][i] : 0.0);
            fprintf(ft, "%.17g,%.17g,%.17g,%.17g,%d\n", b1, b2, v[5][i] * DEG_PER_RAD,
                    v[6][i] * DEG_PER_RAD, spot);
        }
        long n_unseen = 0;
        for (size_t i = 0; i < nv; i++)
            n_unseen += !wseen[i];
        fprintf(fv, "# sunmc %s simulate: validation readings of unit %ld of %s, seed %ld; table "
                    "at exactly b1, b2; %ld points without a spot left out, as in `run`\n",
                SUNMC_VERSION, o->unit, o->config, c->seed, n_unseen);
        fprintf(fv, "b1_deg,b2_deg,x_px,y_px,truth_alpha_deg,truth_beta_deg\n");
        for (size_t i = 0; i < nv; i++)
            if (wseen[i]) {
                fprintf(fv, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", w[0][i] * DEG_PER_RAD,
                        w[1][i] * DEG_PER_RAD, w[2][i], w[3][i], w[4][i] * DEG_PER_RAD,
                        w[5][i] * DEG_PER_RAD);
                n_val++;
            }
        st = out_commit(&os, err, sizeof err);
    } else {
        out_abort(&os);
    }
    if (st == SUNMC_OK) {
        printf("unit %ld of %s (seed %ld): %zu campaign readings (%zu with a spot), %ld "
               "validation readings\n",
               o->unit, c->product, c->seed, n, seen, n_val);
        printf("wrote %s/campaign.csv, %s/truth.csv, %s/validation.csv\n", o->out, o->out,
               o->out);
    } else {
        fprintf(stderr, "sunmc simulate: %s\n", err);
    }
    for (int k = 0; k < 7; k++)
        free(v[k]);
    for (int k = 0; k < 6; k++)
        free(w[k]);
    free(wseen);
    return cli_exit_code(st);
}

int cmd_simulate(int argc, char **argv)
{
    if (cli_wants_help(argc, argv, simulate_help))
        return 0;
    cli_options o;
    int rc = cli_parse(argc, argv, 2, "simulate", "CONFIG unit seed set out quiet", &o);
    if (rc)
        return rc;
    if (!o.config || o.unit < 0 || !o.out || o.n_positional > 0) {
        fprintf(stderr, "sunmc simulate: needs CONFIG, --unit U and --out DIR%s (see sunmc "
                        "simulate --help)\n", o.n_positional ? ", and nothing else" : "");
        return EXIT_BAD_INPUT;
    }
    config_state st;
    if ((rc = cli_config(&o, &st)))
        return rc;
    rc = strcmp(st.cfg.family->name, "ess") == 0 ? simulate_ess(&o, &st.cfg)
                                                 : simulate_dss(&o, &st.cfg);
    config_state_free(&st);
    return rc;
}
