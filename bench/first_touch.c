// What a process's fresh memory costs at first touch, against mapping a file that is in the page
// cache (bench/RESULTS.md, "Topology mapped, not read"). Each line: one way of getting 128 MiB
// of memory and writing it once (or, for the file, mapping it and reading a byte per page).
// Fresh memory is asked for ROUNDS times in one process, munmap'd in between, so the first
// round shows memory that was idle before the process started and the later ones memory the
// process itself just gave back.
//
// usage: cc -O2 -o /tmp/first_touch bench/first_touch.c && /tmp/first_touch [FILE]
#define _GNU_SOURCE
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

enum { ROUNDS = 3 };
static const size_t kBytes = (size_t)128 << 20, kHuge = (size_t)2 << 20;

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + t.tv_nsec * 1e-9;
}

// 128 MiB of fresh anonymous memory on huge pages or 4 KiB ones, written once: milliseconds.
static double touch_fresh(int huge) {
  char* raw = mmap(NULL, kBytes + kHuge, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  char* p = (char*)(((size_t)raw + kHuge - 1) & ~(kHuge - 1));
  madvise(p, kBytes, huge ? MADV_HUGEPAGE : MADV_NOHUGEPAGE);
  const double t0 = now();
  memset(p, 1, kBytes);
  const double ms = (now() - t0) * 1e3;
  munmap(raw, kBytes + kHuge);
  return ms;
}

int main(int argc, char** argv) {
  for (int huge = 1; huge >= 0; --huge) {
    printf("fresh memory, %s pages, 128 MiB written once:", huge ? "2 MiB" : "4 KiB");
    for (int r = 0; r < ROUNDS; ++r) printf(" %.1f ms", touch_fresh(huge));
    printf("\n");
  }
  if (argc > 1) {
    const int fd = open(argv[1], O_RDONLY);
    const off_t size = lseek(fd, 0, SEEK_END);
    const double t0 = now();
    const char* f = mmap(NULL, size, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
    long sum = 0;
    for (off_t i = 0; i < size; i += 4096) sum += f[i];
    printf("%s (%.1f MiB, in the page cache) mapped with MAP_POPULATE and read: %.1f ms (%ld)\n", argv[1],
           size / 1048576.0, (now() - t0) * 1e3, sum & 1);
  }
  return 0;
}
