/* cmd_simulate.c - `sunmc simulate`: one simulated unit's calibration
 * campaign as a lab records it, with the truth behind it. */
#include "cli.h"
#include "family.h"
#include "lab.h"
#include "output.h"
#include "status.h"

#include <stdlib.h>

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

/* Simulate, write the files all or nothing, print what the family says. */
static int simulate(const cli_options *o, const sunmc_config *c, const family_lab *lab)
{
    char err[SUNMC_ERRLEN];
    void *sim = NULL;
    int st = lab->sim_run(c, o->unit, &sim, err, sizeof err);
    if (st != SUNMC_OK) {
        fprintf(stderr, "sunmc simulate: %s\n", err);
        return cli_exit_code(st);
    }
    lab_unit_ref ref = {o->config, o->unit, o->out};
    out_set os;
    FILE *f[LAB_SIM_FILES] = {NULL};
    st = out_begin(&os, o->out, err, sizeof err);
    if (st == SUNMC_OK) {
        st = out_open_all(&os, lab_sim_files, f, LAB_SIM_FILES, err, sizeof err);
        if (st == SUNMC_OK)
            st = lab->sim_write(sim, c, &ref, f);
        if (st == SUNMC_OK)
            st = out_commit(&os, err, sizeof err);
        else
            out_abort(&os);
    }
    if (st == SUNMC_OK) {
        char *note = malloc(LAB_NOTE_MAX);
        if (note) {
            lab->sim_summary(sim, c, &ref, note, LAB_NOTE_MAX);
            fputs(note, stdout);
        }
        free(note);
    } else {
        fprintf(stderr, "sunmc simulate: %s\n", err);
    }
    lab->sim_free(sim);
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
    const family_lab *lab = st.cfg.family->lab;
    if (!lab) {
        fprintf(stderr, "sunmc simulate: the %s family has no lab commands\n",
                st.cfg.family->name);
        rc = EXIT_BAD_INPUT;
    } else {
        rc = simulate(&o, &st.cfg, lab);
    }
    config_state_free(&st);
    return rc;
}
