// LD_PRELOAD shim for the CLI safety tests: a file system that cannot exchange two names.
// renameat2(RENAME_EXCHANGE) fails with EINVAL, as on file systems without the flag (FAT,
// some network and FUSE file systems); every other rename goes to the kernel unchanged. The
// writer then takes its rename-aside path (src/sdk/atomic_write.cpp, putInPlace()), which
// ext4 and tmpfs, accepting the exchange, never reach. Each refused exchange is counted in
// the file MLOD_NO_EXCHANGE_LOG names (one line each), so a test can see that the path ran.

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fcntl.h>
#include <linux/fs.h>
#include <sys/syscall.h>
#include <unistd.h>

extern "C" int renameat2(int olddirfd, const char* oldpath, int newdirfd, const char* newpath, unsigned int flags) {
  if (flags & RENAME_EXCHANGE) {
    if (const char* log = std::getenv("MLOD_NO_EXCHANGE_LOG")) {
      if (std::FILE* out = std::fopen(log, "a")) {
        std::fprintf(out, "refused %s <-> %s\n", oldpath, newpath);
        std::fclose(out);
      }
    }
    errno = EINVAL;
    return -1;
  }
  return static_cast<int>(::syscall(SYS_renameat2, olddirfd, oldpath, newdirfd, newpath, flags));
}
