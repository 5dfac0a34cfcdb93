/* memory.c - the memory a run needs, checked before any work. */
#include "memory.h"
#include "family.h"
#include "status.h"

#include <stdio.h>
#include <sys/resource.h>
#include <unistd.h>

void memory_text(double bytes, char *buf, size_t len)
{
    static const char *const unit[] = {"bytes", "kB", "MB", "GB", "TB", "PB"};
    int i = 0;
    while (bytes >= 1000.0 && i < 5) {
        bytes /= 1000.0;
        i++;
    }
    snprintf(buf, len, i == 0 ? "%.0f %s" : "%.3g %s", bytes, unit[i]);
}

double memory_available_bytes(void)
{
    long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
    double avail = pages > 0 && size > 0 ? (double)pages * (double)size : 0.0;
    static const int limits[] = {RLIMIT_AS, RLIMIT_DATA};
    for (int i = 0; i < 2; i++) {
        struct rlimit rl;
        if (getrlimit(limits[i], &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
            (avail <= 0 || (double)rl.rlim_cur < avail))
            avail = (double)rl.rlim_cur;
    }
    return avail;
}

static double workspace_bytes(const sunmc_config *c)
{
    const sensor_family *fam = c->family;
    return fam && fam->workspace_bytes ? fam->workspace_bytes(c) : 0.0;
}

/* The statistics keep each unit's RMS after per angle and band in arrays
 * that grow by half: up to 1.5 times what they hold. */
#define MEMORY_GROWTH 1.5

double memory_run_bytes(const sunmc_config *c, long units, int threads, int in_memory)
{
    double ws = (double)(threads > 0 ? threads : 1) * workspace_bytes(c);
    if (in_memory)
        return (double)units * (double)sizeof(unit_result) + ws;
    long block = c->block_units < units ? c->block_units : units;
    double cells = c->family ? (double)c->family->n_angles(c) * c->bands_deg.n : 0.0;
    return MEMORY_GROWTH * (double)units * cells * (double)sizeof(double) +
           (double)block * (double)sizeof(unit_result) + ws;
}

int memory_check_workspace(const sunmc_config *c, char *err, size_t errlen)
{
    double ws = workspace_bytes(c);
    if (ws <= MEMORY_WORKSPACE_MAX_BYTES)
        return SUNMC_OK;
    char need[32], max[32];
    memory_text(ws, need, sizeof need);
    memory_text(MEMORY_WORKSPACE_MAX_BYTES, max, sizeof max);
    return sunmc_fail(err, errlen, SUNMC_EINPUT,
                      "campaign and validation grids: their readings and the fit's Jacobian "
                      "would need %s per thread (at most %s): take a coarser step or a smaller "
                      "range",
                      need, max);
}

int memory_check_run(const sunmc_config *c, long first, long end, int threads, int in_memory,
                     double limit_bytes, char *err, size_t errlen)
{
    long units = end - first;
    double need = memory_run_bytes(c, units, threads, in_memory);
    double limit = limit_bytes > 0 ? limit_bytes : memory_available_bytes();
    if (limit <= 0 || need <= limit)
        return SUNMC_OK;
    char t_need[32], t_lim[32], t_unit[32];
    memory_text(need, t_need, sizeof t_need);
    memory_text(limit, t_lim, sizeof t_lim);
    double fixed = memory_run_bytes(c, 0, threads, in_memory);
    double per_unit = (memory_run_bytes(c, 1000000, threads, in_memory) -
                       memory_run_bytes(c, 0, threads, in_memory) -
                       (in_memory ? 0 : (double)c->block_units * (double)sizeof(unit_result))) /
                      1e6;
    memory_text(per_unit, t_unit, sizeof t_unit);
    long fit = fixed < limit && per_unit > 0 ? (long)((limit - fixed) / per_unit) : 0;
    char range[64];
    if (first == 0)
        snprintf(range, sizeof range, "%ld", end);
    else
        snprintf(range, sizeof range, "%ld:%ld", first, end);
    return sunmc_fail(err, errlen, SUNMC_EINPUT,
                      "--units %s: %ld units need %s of memory (%s per unit, plus the %d threads' "
                      "workspaces), more than the %s this process may use (physical memory, "
                      "ulimit); run at most about %ld units at a time (--units FIRST:END gives the same rows as the "
                      "whole run)",
                      range, units, t_need, t_unit, threads > 0 ? threads : 1, t_lim, fit);
}
