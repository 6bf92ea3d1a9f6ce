// writeFileAtomically() and writeFilesAtomically() (exporter.h): what every exporter writes
// goes through here, so the rules of docs/architecture.md section 9 (nothing lost, no
// partial file) hold for all of them:
// - each file is written to a temporary beside it (".NAME.mlod-tmp-PID-XXXXXX"), in full,
//   and fsync'ed before it takes the file's place, so a crash never leaves a torn file;
// - a set of files (a bundle and its manifest) takes its places in order, each by
//   renameat2(RENAME_EXCHANGE): the new file and the one it replaces swap names in one step,
//   so the temporary's name then holds the previous version. Where the file system cannot
//   exchange (EINVAL, ENOSYS), the previous version is renamed aside
//   (".NAME.mlod-old-PID-XXXXXX") and the new file renamed in; only where that cannot be
//   done either is a copy kept. No hard link is needed, so another user's file (which
//   fs.protected_hardlinks, Debian's default, forbids linking) is kept as surely as one's
//   own. When a file cannot take its place, the files already placed get their previous
//   version back by rename (or go, where there was none): after any failure the previous
//   set is intact. A kill between two renames can leave a new bundle beside an old
//   manifest: the manifest carries the bundle's size and CRC-32, so a reader tells
//   (motionlod info does);
// - the renames of a set hold an exclusive flock() on each of its folders, so that two
//   writers of the same set (four exports of different clips to one .mlodb at once) land
//   one whole set after the other, never one's bundle beside the other's manifest;
// - what a killed writer left behind (its PID no longer runs) is cleared the next time the
//   same file is written: its temporaries go, and a version it had renamed aside goes back
//   into place where nothing took it, or goes too;
// - a failure names the file and the system's reason ("No space left on device").
// POSIX calls, not QSaveFile: Qt's buffered writes report a full disk as "Unknown error".

#include "sdk/exporter.h"

#include <QFile>
#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <string>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace mlod {

namespace {

namespace fs = std::filesystem;

constexpr const char* kTemporaryTag = ".mlod-tmp-";
constexpr const char* kKeptTag = ".mlod-old-";

std::string bytesOf(const QString& path) {
  return QFile::encodeName(path).toStdString();
}

ExportResult failure(const QString& path, const std::string& reason) {
  return ExportResult::failure(QStringLiteral("%1: cannot write: %2").arg(path, QString::fromStdString(reason)));
}

std::string folderOf(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

// Clears what a killed writer of `path` left beside it, named with a PID that runs no more:
// temporaries ".NAME.mlod-tmp-PID-…" go; a previous version renamed aside,
// ".NAME.mlod-old-PID-…", goes back to `path` where nothing took its place (the writer died
// between its two renames), and goes otherwise.
void removeLeftovers(const std::string& path) {
  const std::string name = fs::path(path).filename().string();
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(folderOf(path), error)) {
    const std::string left = entry.path().filename().string();
    for (const char* tag : {kTemporaryTag, kKeptTag}) {
      const std::string prefix = "." + name + tag;
      if (left.rfind(prefix, 0) != 0)
        continue;
      const long pid = std::strtol(left.c_str() + prefix.size(), nullptr, 10);
      if (pid <= 0 || pid == long(::getpid()) || ::kill(pid_t(pid), 0) == 0 || errno != ESRCH)
        continue;
      struct stat info {};
      const bool vacant = ::lstat(path.c_str(), &info) != 0 && errno == ENOENT;
      if (tag == kKeptTag && vacant)
        ::rename(entry.path().c_str(), path.c_str());
      else
        ::unlink(entry.path().c_str());
    }
  }
}

bool writeAll(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t written = ::write(fd, data, size);
    if (written < 0 && errno == EINTR)
      continue;
    if (written <= 0) {
      if (written == 0)
        errno = EIO;
      return false;
    }
    data += written;
    size -= std::size_t(written);
  }
  return true;
}

// `data` in a fresh temporary beside `path`, fsync'ed; its name, or empty and errno.
std::string writeTemporary(const std::string& path, const QByteArray& data) {
  std::string temporary = folderOf(path) + "/." + fs::path(path).filename().string() + kTemporaryTag +
                          std::to_string(::getpid()) + "-XXXXXX";
  const int fd = ::mkostemp(temporary.data(), O_CLOEXEC);
  if (fd < 0)
    return {};
  const bool written =
      ::fchmod(fd, 0644) == 0 && writeAll(fd, data.constData(), std::size_t(data.size())) && ::fsync(fd) == 0;
  const int writeErrno = errno;
  if (::close(fd) != 0 || !written) {
    const int reason = written ? errno : writeErrno;
    ::unlink(temporary.c_str());
    errno = reason;
    return {};
  }
  return temporary;
}

// A copy of the file at `from` as `to` (created, fsync'ed): the last resort to keep a
// previous version, where it can neither be exchanged nor renamed aside. False and errno.
bool copyFile(const std::string& from, const std::string& to) {
  const int in = ::open(from.c_str(), O_RDONLY | O_CLOEXEC);
  if (in < 0)
    return false;
  const int out = ::open(to.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (out < 0) {
    const int reason = errno;
    ::close(in);
    errno = reason;
    return false;
  }
  std::vector<char> buffer(1 << 20);
  bool ok = true;
  for (;;) {
    const ssize_t n = ::read(in, buffer.data(), buffer.size());
    if (n < 0 && errno == EINTR)
      continue;
    if (n <= 0) {
      ok = n == 0;
      break;
    }
    if (!writeAll(out, buffer.data(), std::size_t(n))) {
      ok = false;
      break;
    }
  }
  ok = ok && ::fsync(out) == 0;
  const int reason = errno;
  ::close(in);
  if (::close(out) != 0)
    ok = false;
  if (!ok) {
    ::unlink(to.c_str());
    errno = reason;
  }
  return ok;
}

// Exclusive flock()s on folders, taken in name order (no two writers wait on each other),
// released when it goes: a set's renames run whole, one writer's after another's.
class FolderLocks {
public:
  explicit FolderLocks(std::vector<std::string> folders) {
    std::sort(folders.begin(), folders.end());
    folders.erase(std::unique(folders.begin(), folders.end()), folders.end());
    for (const std::string& folder : folders) {
      const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
      if (fd < 0)
        continue; // the renames then fail and say why
      while (::flock(fd, LOCK_EX) != 0 && errno == EINTR) {
      }
      m_fds.push_back(fd);
    }
  }
  ~FolderLocks() {
    for (const int fd : m_fds)
      ::close(fd); // releases the lock
  }
  FolderLocks(const FolderLocks&) = delete;
  FolderLocks& operator=(const FolderLocks&) = delete;

private:
  std::vector<int> m_fds;
};

void syncFolder(const std::string& path) {
  const int fd = ::open(folderOf(path).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

// One file of a set on its way into place.
struct PlacedFile {
  QString name;          // as the caller gave it
  std::string path;      // its bytes
  std::string temporary; // the new content, until it is in place
  std::string kept;      // once in place: the version it replaced (empty: there was none)
};

// `file.temporary` into place at `file.path`, keeping what was there in `file.kept` (under
// the temporary's name after an exchange, the kept name otherwise). False and errno, with
// `file.path` as it was.
bool putInPlace(PlacedFile& file) {
  struct stat info {};
  // a folder is never replaced: the rename refuses it (EISDIR), and the failure says so
  if (::lstat(file.path.c_str(), &info) != 0 || S_ISDIR(info.st_mode)) {
    if (::rename(file.temporary.c_str(), file.path.c_str()) != 0)
      return false;
    file.temporary.clear();
    return true;
  }
  if (::renameat2(AT_FDCWD, file.temporary.c_str(), AT_FDCWD, file.path.c_str(), RENAME_EXCHANGE) == 0) {
    file.kept = std::move(file.temporary);
    file.temporary.clear();
    return true;
  }
  if (errno != EINVAL && errno != ENOSYS)
    return false; // the file system could exchange; this file may not be replaced
  std::string aside = file.temporary;
  aside.replace(aside.rfind(kTemporaryTag), std::strlen(kTemporaryTag), kKeptTag);
  // note: between these two renames `path` is vacant; a writer killed there leaves the
  // previous version aside, and removeLeftovers() puts it back
  const bool movedAside = ::rename(file.path.c_str(), aside.c_str()) == 0;
  if (!movedAside && !copyFile(file.path, aside))
    return false;
  if (::rename(file.temporary.c_str(), file.path.c_str()) != 0) {
    const int reason = errno;
    if (movedAside)
      ::rename(aside.c_str(), file.path.c_str());
    else
      ::unlink(aside.c_str());
    errno = reason;
    return false;
  }
  file.temporary.clear();
  file.kept = std::move(aside);
  return true;
}

// A file already in place gets its previous version back, or goes where there was none.
// Should the rename fail, the previous version stays beside it under its kept name.
void putBack(PlacedFile& file) {
  if (file.kept.empty())
    ::unlink(file.path.c_str());
  else
    ::rename(file.kept.c_str(), file.path.c_str());
  file.kept.clear();
}

} // namespace

ExportResult writeFileAtomically(const QString& path, const QByteArray& data) {
  ExportResult result = writeFilesAtomically({{path, data}});
  if (result.ok)
    result.message = QStringLiteral("wrote %1 (%2 bytes)").arg(path).arg(data.size());
  return result;
}

ExportResult writeFilesAtomically(const QList<QPair<QString, QByteArray>>& files) {
  std::vector<PlacedFile> entries;
  const auto discard = [&entries] {
    for (const PlacedFile& entry : entries) {
      if (!entry.temporary.empty())
        ::unlink(entry.temporary.c_str());
      if (!entry.kept.empty())
        ::unlink(entry.kept.c_str());
    }
  };
  for (const auto& [name, data] : files) {
    PlacedFile entry{name, bytesOf(name), {}, {}};
    removeLeftovers(entry.path);
    entry.temporary = writeTemporary(entry.path, data);
    if (entry.temporary.empty()) {
      const std::string reason = std::strerror(errno);
      discard();
      return failure(name, reason);
    }
    entries.push_back(std::move(entry));
  }
  // from here to the last rename, one writer of these folders at a time
  std::vector<std::string> folders;
  for (const PlacedFile& entry : entries)
    folders.push_back(folderOf(entry.path));
  const FolderLocks locks(std::move(folders));
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (putInPlace(entries[i]))
      continue;
    const std::string reason = std::strerror(errno);
    for (std::size_t k = 0; k < i; ++k)
      putBack(entries[k]);
    discard();
    return failure(entries[i].name, reason);
  }
  for (const PlacedFile& entry : entries)
    syncFolder(entry.path);
  discard(); // the previous versions
  qint64 bytes = 0;
  QStringList names;
  for (const auto& [name, data] : files) {
    names << name;
    bytes += data.size();
  }
  return ExportResult::success(QStringLiteral("wrote %1 (%2 bytes)").arg(names.join(", ")).arg(bytes));
}

} // namespace mlod
