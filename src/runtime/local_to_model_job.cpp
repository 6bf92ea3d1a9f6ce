#include "runtime/local_to_model_job.h"

namespace mlod {

bool LocalToModelJob::validate() const {
  const std::size_t count = parents.size();
  if (count > 32767 || locals.size() != count || out_models.size() != count)
    return false;
  for (std::size_t i = 0; i < count; ++i)
    if (parents[i] < -1 || parents[i] >= static_cast<std::int16_t>(i))
      return false;
  return true;
}

bool LocalToModelJob::run() const {
  if (!validate())
    return false;
  const glm::mat4 identity(1.0f);
  const glm::mat4& top = root ? *root : identity;
  for (std::size_t i = 0; i < parents.size(); ++i) {
    const std::int16_t parent = parents[i];
    out_models[i] = (parent < 0 ? top : out_models[static_cast<std::size_t>(parent)]) * locals[i];
  }
  return true;
}

} // namespace mlod
