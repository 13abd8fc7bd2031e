#!/usr/bin/env bash
# direct-io where the file system refuses O_DIRECT: a preloaded shim makes open(O_DIRECT) fail
# with EINVAL, as ext4 with data=journal, some network and FUSE file systems do. play must warn
# once, read buffered, and render the frames of a plain buffered level.
source "$(dirname "$0")/common.bash"
cd "$WORK"
cat >refuse.c <<'C'
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
static int refuse(int flags) {
  if (!(flags & O_DIRECT)) return 0;
  const char* mark = getenv("REFUSE_MARK");
  if (mark) fclose(fopen(mark, "w"));
  errno = EINVAL;
  return 1;
}
#define SHIM(name)                                                   \
  int name(const char* path, int flags, ...) {                        \
    va_list ap;                                                       \
    va_start(ap, flags);                                              \
    const mode_t mode = (mode_t)va_arg(ap, int);                      \
    va_end(ap);                                                       \
    if (refuse(flags)) return -1;                                     \
    int (*real)(const char*, int, ...) = dlsym(RTLD_NEXT, #name);     \
    return real(path, flags, mode);                                   \
  }
SHIM(open)
SHIM(open64)
C
cc -shared -fPIC -O1 -o refuse.so refuse.c -ldl || fail "cannot build the O_DIRECT shim"
"$VS" demo jet --cells 10000 --steps 3 -o ds -q >/dev/null
"$VS" play ds --pipeline async-io --size 32x24 -q -o "plain_%d.png" >/dev/null
REFUSE_MARK="$WORK/refused" LD_PRELOAD="$WORK/refuse.so" \
  "$VS" play ds --pipeline direct-io --size 32x24 -q -o "direct_%d.png" >out.txt 2>err.txt || fail "play failed: $(cat err.txt)"
if [ ! -f refused ]; then
  # A statically linked sanitizer runtime can shadow the shim's open(): nothing was refused.
  echo "skip: the shim was not interposed in this build"; exit 0
fi
[ "$(grep -c 'refuses O_DIRECT' err.txt)" = 1 ] || fail "expected one warning, stderr: $(cat err.txt)"
grep -q "reads: .*buffered (O_DIRECT refused)" out.txt || fail "report does not say the reads were buffered: $(cat out.txt)"
for i in 0 1 2; do cmp -s plain_$i.png direct_$i.png || fail "frame $i differs from buffered play"; done
echo "ok: O_DIRECT refused -> one warning, buffered reads, same frames"
