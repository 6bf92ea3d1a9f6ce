#pragma once
// Runs `motionlod` with arguments and captures what it printed and its exit status.

#include <string>
#include <vector>

namespace mlod::test {

struct CliRun {
  int status = -1; // exit status; 128 + signal when killed by one
  std::string out;
  std::string err;
};

CliRun runMotionlod(const std::vector<std::string>& arguments);

} // namespace mlod::test
