#include "runtime/input_file.h"

#include <fstream>

namespace mlod {

namespace {

std::string bytesText(std::uint64_t bytes) {
  if (bytes >= (std::uint64_t(1) << 30) && bytes % (std::uint64_t(1) << 30) == 0)
    return std::to_string(bytes >> 30) + " GiB";
  if (bytes >= (std::uint64_t(1) << 20) && bytes % (std::uint64_t(1) << 20) == 0)
    return std::to_string(bytes >> 20) + " MiB";
  return std::to_string(bytes) + " bytes";
}

} // namespace

std::string inputFileProblem(const std::filesystem::path& path, std::uint64_t maxBytes) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(path, error); // follows symlinks
  switch (status.type()) {
  case fs::file_type::regular:
    break;
  case fs::file_type::not_found:
    return fs::is_symlink(fs::symlink_status(path, error)) ? "it is a dangling symbolic link" : "no such file";
  case fs::file_type::directory:
    return "it is a directory, not a file";
  case fs::file_type::fifo:
    return "it is a FIFO (named pipe), not a regular file";
  case fs::file_type::socket:
    return "it is a socket, not a regular file";
  case fs::file_type::character:
  case fs::file_type::block:
    return "it is a device, not a regular file";
  default:
    return error ? "cannot read it: " + error.message() : "it is not a regular file";
  }
  const std::uintmax_t size = fs::file_size(path, error);
  if (error)
    return "cannot read it: " + error.message();
  if (size > maxBytes)
    return "it is " + std::to_string(size) + " bytes, more than the " + bytesText(maxBytes) + " this reader takes";
  return {};
}

std::optional<std::string> readInputFile(const std::filesystem::path& path, std::uint64_t maxBytes,
                                         std::string* out_error) {
  const auto fail = [out_error](std::string reason) -> std::optional<std::string> {
    if (out_error)
      *out_error = std::move(reason);
    return std::nullopt;
  };
  if (std::string problem = inputFileProblem(path, maxBytes); !problem.empty())
    return fail(std::move(problem));
  std::ifstream file(path, std::ios::binary);
  if (!file)
    return fail("cannot open it for reading");
  std::string bytes;
  std::error_code error;
  bytes.reserve(static_cast<std::size_t>(std::filesystem::file_size(path, error)));
  char buffer[1 << 16];
  while (file) {
    file.read(buffer, sizeof buffer);
    bytes.append(buffer, static_cast<std::size_t>(file.gcount()));
    if (bytes.size() > maxBytes)
      return fail("it grew past the " + bytesText(maxBytes) + " this reader takes while it was read");
  }
  if (file.bad())
    return fail("cannot read it");
  return bytes;
}

} // namespace mlod
