/* registry.c - the table of sensor families: the one deliberate reference
 * from core to the families (each defines its struct in its *_family.c). */
#include "registry.h"

#include <string.h>

extern const sensor_family ess_family;
extern const sensor_family dss_family;

/* Built-in families first, in the order the reference config lists them;
 * sensor_family_register appends. */
static const sensor_family *sensor_families[CONFIG_FAMILIES_MAX] = {&ess_family, &dss_family};
static int n_families = 2;

int sensor_family_count(void)
{
    return n_families;
}

const sensor_family *sensor_family_at(int i)
{
    return i >= 0 && i < n_families ? sensor_families[i] : NULL;
}

const sensor_family *sensor_family_find(const char *name)
{
    for (int i = 0; i < n_families; i++)
        if (strcmp(sensor_families[i]->name, name) == 0)
            return sensor_families[i];
    return NULL;
}

int sensor_family_register(const sensor_family *f)
{
    if (n_families >= CONFIG_FAMILIES_MAX || sensor_family_find(f->name))
        return -1;
    sensor_families[n_families++] = f;
    return 0;
}
