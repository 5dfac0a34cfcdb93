/* registry.c - the table of sensor families: the one deliberate reference
 * from core to the families (each defines its struct in its folder). */
#include "registry.h"

#include <string.h>

/* The families, one line each (F(name): the folder src/name/ defines
 * `const sensor_family name_family`), in the order the reference config
 * lists them; the first is sensor.family's default. */
#define SUNMC_FAMILIES(F) \
    F(ess)                \
    F(dss)                \
    F(psd)

#define FAMILY_DECLARE(name) extern const sensor_family name##_family;
#define FAMILY_ENTRY(name) &name##_family,
SUNMC_FAMILIES(FAMILY_DECLARE)

/* Empty slots are NULL; sensor_family_register fills the next one (tests only). */
static const sensor_family *sensor_families[CONFIG_FAMILIES_MAX] = {SUNMC_FAMILIES(FAMILY_ENTRY)};

int sensor_family_count(void)
{
    int n = 0;
    while (n < CONFIG_FAMILIES_MAX && sensor_families[n])
        n++;
    return n;
}

const sensor_family *sensor_family_at(int i)
{
    return i >= 0 && i < sensor_family_count() ? sensor_families[i] : NULL;
}

const sensor_family *sensor_family_find(const char *name)
{
    for (int i = 0; i < sensor_family_count(); i++)
        if (strcmp(sensor_families[i]->name, name) == 0)
            return sensor_families[i];
    return NULL;
}

int sensor_family_register(const sensor_family *f)
{
    int n = sensor_family_count();
    if (n >= CONFIG_FAMILIES_MAX || sensor_family_find(f->name))
        return -1;
    sensor_families[n] = f;
    return 0;
}
