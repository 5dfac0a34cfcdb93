/* main_stubs.c - commands not built yet. */
#include "main.h"

static int not_yet(const char *name)
{
    fprintf(stderr, "sunmc %s: not available in this version\n", name);
    return 1;
}

int cmd_curve(int argc, char **argv) { return not_yet("curve"); }
