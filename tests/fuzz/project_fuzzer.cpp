// libFuzzer target for the project reader (core/project.h): arbitrary text as a .mlod. Every
// input gives a Project that validates or an Error; never a crash, an exception, or a
// build that runs for minutes (the level cap: a project of 70,000 levels did).
#include "core/project.h"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const mlod::Result<mlod::Project> project =
      mlod::projectFromJson(std::string_view(reinterpret_cast<const char*>(data), size));
  if (project) {
    if (project->validate() || project->levelCount() > mlod::kMaxProjectLevels)
      std::abort(); // a project that was read must keep its rules
    // what was read writes and reads back to the same project
    const mlod::Result<mlod::Project> again = mlod::projectFromJson(mlod::projectToJson(*project));
    if (!again || !(*again == *project))
      std::abort();
  }
  return 0;
}
