/* fuzz_util.h - shared by the libFuzzer harnesses (make fuzz): the input
 * as a file the readers can open by name, without touching the disk. */
#ifndef SUNMC_FUZZ_UTIL_H
#define SUNMC_FUZZ_UTIL_H

#define _GNU_SOURCE
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <sys/mman.h>
#include <unistd.h>

/* An in-memory file holding data[size]; its path ("/proc/self/fd/N") goes
 * to path.  Returns the descriptor (close it after use), -1 on failure. */
static inline int fuzz_file(const uint8_t *data, size_t size, char *path, size_t len)
{
    int fd = memfd_create("sunmc-fuzz", 0);
    if (fd < 0)
        return -1;
    size_t done = 0;
    while (done < size) {
        ssize_t w = write(fd, data + done, size - done);
        if (w <= 0) {
            close(fd);
            return -1;
        }
        done += (size_t)w;
    }
    snprintf(path, len, "/proc/self/fd/%d", fd);
    return fd;
}

#endif
