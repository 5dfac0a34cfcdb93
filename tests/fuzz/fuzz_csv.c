/* fuzz_csv.c - libFuzzer harness: any bytes as a lab data file (csv_read),
 * then every column looked up by its own name and parsed as numbers, and
 * the columns calibrate asks for. */
#include "fuzz_util.h"

#include "csv.h"
#include "status.h"

#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[64], err[SUNMC_ERRLEN];
    int fd = fuzz_file(data, size, path, sizeof path);
    if (fd < 0)
        return 0;
    csv_table *t = NULL;
    if (csv_read(path, &t, err, sizeof err) == SUNMC_OK) {
        double *v = malloc((t->n_rows + 1) * sizeof *v);
        for (int j = 0; v && j < t->n_cols; j++) {
            int col;
            if (csv_column(t, t->names[j], 1, &col, err, sizeof err) == SUNMC_OK)
                csv_doubles(t, col, v, err, sizeof err);
        }
        static const char *const wanted[] = {"alpha_deg", "beta_deg", "output_deg", "weight",
                                             "b1_deg", "b2_deg", "x_px", "y_px"};
        for (size_t i = 0; i < sizeof wanted / sizeof wanted[0]; i++) {
            int col;
            csv_column(t, wanted[i], 0, &col, err, sizeof err);
        }
        csv_require_rows(t, 9, "the fit", err, sizeof err);
        free(v);
        csv_free(t);
    }
    close(fd);
    return 0;
}
