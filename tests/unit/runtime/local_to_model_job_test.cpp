#include "runtime/local_to_model_job.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <vector>

namespace mlod {
namespace {

// A chain root -> a -> b, each 10 cm along x, a turned 90 degrees about z.
struct Chain {
  std::vector<std::int16_t> parents{-1, 0, 1};
  std::vector<glm::mat4> locals{
      glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, 0)),
      glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(10, 0, 0)), glm::radians(90.0f), glm::vec3(0, 0, 1)),
      glm::translate(glm::mat4(1.0f), glm::vec3(10, 0, 0))};
  std::vector<glm::mat4> models = std::vector<glm::mat4>(3, glm::mat4(0.0f));
  LocalToModelJob job() {
    LocalToModelJob j;
    j.parents = parents;
    j.locals = locals;
    j.out_models = models;
    return j;
  }
};

// Guards the hierarchy walk: the child of a turned joint moves along the turned axis.
TEST(LocalToModelJob, ComposesParentsFirst) {
  Chain chain;
  ASSERT_TRUE(chain.job().run());
  EXPECT_NEAR(chain.models[2][3].x, 10.0f, 1e-5f);
  EXPECT_NEAR(chain.models[2][3].y, 10.0f, 1e-5f);
}

// Guards the optional root transform above every root.
TEST(LocalToModelJob, AppliesRootTransform) {
  Chain chain;
  const glm::mat4 lift = glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, 5));
  LocalToModelJob job = chain.job();
  job.root = &lift;
  ASSERT_TRUE(job.run());
  EXPECT_NEAR(chain.models[2][3].z, 5.0f, 1e-6f);
}

// Guards validate(): each invalid input in turn fails, and run() then writes nothing.
TEST(LocalToModelJob, RejectsInvalidJobs) {
  {
    Chain chain;
    std::vector<glm::mat4> small(2);
    LocalToModelJob job = chain.job();
    job.out_models = small;
    EXPECT_FALSE(job.validate());
  }
  {
    Chain chain;
    LocalToModelJob job = chain.job();
    job.locals = std::span<const glm::mat4>(chain.locals.data(), 2);
    EXPECT_FALSE(job.validate());
  }
  {
    Chain chain;
    chain.parents[1] = 2; // parent after child
    EXPECT_FALSE(chain.job().validate());
    EXPECT_FALSE(chain.job().run());
    EXPECT_EQ(chain.models[0], glm::mat4(0.0f));
  }
  {
    Chain chain;
    chain.parents[2] = -2;
    EXPECT_FALSE(chain.job().validate());
  }
  LocalToModelJob empty;
  EXPECT_TRUE(empty.validate()); // zero joints is a valid, empty job
}

} // namespace
} // namespace mlod
