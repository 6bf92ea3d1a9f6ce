#include "io/isolated_import.h"

#include "io/asset_stream.h"
#include "io/importer.h"
#include "runtime/input_file.h"

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#if defined(__SANITIZE_ADDRESS__)
#define MLOD_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MLOD_ASAN 1
#endif
#endif

namespace mlod {

namespace {

bool writeAll(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t written = ::write(fd, data, size);
    if (written < 0 && errno == EINTR)
      continue;
    if (written <= 0)
      return false;
    data += written;
    size -= static_cast<std::size_t>(written);
  }
  return true;
}

#ifdef MLOD_ASAN
// The process's address space in bytes (the first field of /proc/self/statm, in pages).
std::size_t mappedBytes() {
  std::size_t pages = 0;
  if (std::FILE* statm = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(statm, "%zu", &pages) != 1)
      pages = 0;
    std::fclose(statm);
  }
  return pages * static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
}
#endif

[[noreturn]] void runChild(int fd, pid_t parent, const std::string& path, const ImportOptions& options,
                           std::size_t memoryBytes) {
  // The worker dies with its parent: killed (kill -9) while it imports, the parent can no
  // longer stop it, and a stuck Assimp would spin at 100% CPU forever. PR_SET_PDEATHSIG
  // covers a parent that dies from now on; the getppid() check one that died before it.
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent)
    ::_exit(4);
  // Keep only the pipe (as fd 3) and the standard streams: a worker started by another
  // thread at the same moment (batch --jobs) must not hold this worker's pipe open, or
  // the parent would wait for that one's end too.
  if (fd != 3) {
    ::dup2(fd, 3);
    fd = 3;
  }
  ::close_range(4, ~0u, 0);
  std::signal(SIGPIPE, SIG_IGN);
  std::signal(SIGINT, SIG_DFL); // the parent's handlers (Ctrl+C cancels) are not the worker's
  std::signal(SIGTERM, SIG_DFL);
  if (memoryBytes > 0) {
#ifdef MLOD_ASAN
    // ASan reserves terabytes of address space up front (shadow, allocator regions), so
    // there the limit is on growth: what the worker has mapped now, plus memoryBytes. An
    // allocation past it ends the worker with ASan's out-of-memory report, as the bad_alloc
    // of a release build would.
    memoryBytes += mappedBytes();
#endif
    rlimit limit{memoryBytes, memoryBytes};
    ::setrlimit(RLIMIT_AS, &limit);
  }
#ifdef MLOD_TESTING
  // Tests of stopping a stuck import (Ctrl+C, kill -9, a cancel, the timeout) need an
  // import that never ends; nothing Assimp reads can block any more (a FIFO side file is
  // refused), so a worker whose file is the one this variable names blocks as a stuck
  // Assimp would, until it is killed. Only test builds (mlod_io_testing) have this hook.
  if (const char* stuck = std::getenv(kStuckImportVariable); stuck && path == stuck) {
    std::fprintf(stderr, "import worker: %s names %s: blocking until stopped (a test hook)\n", kStuckImportVariable,
                 stuck);
    for (;;)
      ::pause();
  }
#endif
  Result<Asset> result = importAsset(path, options);
  bool sent = false;
  if (result.ok()) {
    // streamed: a second copy of a long clip would double the worker's peak memory
    sent = writeAll(fd, "A", 1) &&
           writeAssetStream(result.value(), [fd](const char* data, std::size_t size) { return writeAll(fd, data, size); });
  } else {
    const std::string bytes = "E" + result.message();
    sent = writeAll(fd, bytes.data(), bytes.size());
  }
  ::close(fd);
  ::_exit(sent ? 0 : 3);
}

} // namespace

Result<Asset> importAssetIsolated(const std::string& path, const ImportOptions& options,
                                  const IsolationLimits& limits) {
  // a FIFO, a device or a huge file is refused here, before a worker is started for it
  if (std::string problem = inputFileProblem(path, kMaxImportFileBytes); !problem.empty())
    return Error(problem);
  const pid_t parent = ::getpid();
  int fds[2];
  if (::pipe(fds) != 0)
    return Error(std::string("cannot start the import worker: ") + std::strerror(errno));
  const pid_t child = ::fork();
  if (child < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return Error(std::string("cannot start the import worker: ") + std::strerror(errno));
  }
  if (child == 0) {
    ::close(fds[0]);
    runChild(fds[1], parent, path, options, limits.memoryBytes);
  }
  ::close(fds[1]);

  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration<double>(limits.timeoutSeconds);
  std::string bytes;
  std::string stopped;
  char buffer[1 << 16];
  for (;;) {
    if (limits.cancel && limits.cancel->load()) {
      stopped = "import cancelled";
      break;
    }
    if (limits.timeoutSeconds > 0 && Clock::now() >= deadline) {
      stopped = "import stopped after " + std::to_string(static_cast<int>(limits.timeoutSeconds)) +
                " s: the importer did not finish (the file may be broken)";
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int ready = ::poll(&p, 1, 50);
    if (ready < 0 && errno != EINTR)
      break;
    if (ready <= 0)
      continue;
    const ssize_t got = ::read(fds[0], buffer, sizeof(buffer));
    if (got < 0 && errno == EINTR)
      continue;
    if (got <= 0)
      break; // end of stream: the child finished or died
    bytes.append(buffer, static_cast<std::size_t>(got));
  }
  ::close(fds[0]);
  if (!stopped.empty())
    ::kill(child, SIGKILL);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  if (!stopped.empty())
    return Error(stopped);
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    return Error("the importer crashed on this file (signal " + std::to_string(sig) + ", " + strsignal(sig) + ")");
  }
  if (bytes.empty())
    return Error("the importer stopped without an answer (exit status " + std::to_string(WEXITSTATUS(status)) + ")");
  if (bytes[0] == 'E')
    return Error(bytes.substr(1));
  return readAssetStream(std::string_view(bytes).substr(1));
}

} // namespace mlod
