// Preloaded by lock_files_test.sh: flock refused as a Lustre mount with
// noflock refuses it, so that wearscar's lock-file fallback runs.
#include <sys/file.h>

#include <cerrno>

extern "C" int flock(int /*fd*/, int /*operation*/) {
  errno = ENOLCK;
  return -1;
}
