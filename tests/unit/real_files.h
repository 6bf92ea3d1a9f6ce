#pragma once
// The real files that tests of a general claim run on: tests/data/expected_counts.json's
// "fixtures" (every skinned character of Debian's assimp-testmodels that imports with a
// mesh of >= 500 triangles, and BVH clips), one list for every test, so a claim proven on
// one file is proven on all of them. Parametrise with
//   INSTANTIATE_TEST_SUITE_P(Characters, Suite, ::testing::ValuesIn(test::fixtureCharacters()),
//                            test::fixtureName);
// Needs MLOD_TEST_DATA_DIR and nlohmann_json.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <string>
#include <vector>

namespace mlod::test {

inline const nlohmann::json& fixtureTable() {
  static const nlohmann::json fixtures = [] {
    std::ifstream in(std::string(MLOD_TEST_DATA_DIR) + "/expected_counts.json");
    const nlohmann::json table = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    const auto found = table.is_object() ? table.find("fixtures") : table.end();
    return found != table.end() && found->is_object() ? *found : nlohmann::json::object();
  }();
  return fixtures;
}

// The strings of fixtureTable()'s array `key`, or of member `member` of its objects, taking
// only the objects whose boolean `flag` (null: any) is true.
inline std::vector<std::string> fixtureStrings(const char* key, const char* member, const char* flag) {
  std::vector<std::string> out;
  const auto list = fixtureTable().find(key);
  if (list == fixtureTable().end() || !list->is_array())
    return out;
  for (const nlohmann::json& entry : *list) {
    const nlohmann::json* text = &entry;
    if (member) {
      const auto found = entry.is_object() ? entry.find(member) : entry.end();
      const auto wanted = flag && entry.is_object() ? entry.find(flag) : entry.end();
      if (found == entry.end() || (flag && (wanted == entry.end() || !wanted->is_boolean() || !wanted->get<bool>())))
        continue;
      text = &*found;
    }
    if (text->is_string())
      out.push_back(text->get<std::string>());
  }
  return out;
}

// Paths relative to MLOD_ASSIMP_MODELS. `flag` (may be null: all of them): only the
// characters whose entry sets it: "animated" (a skeleton of >= 2 joints and a clip of >= 3
// frames: a claim about motion), "still" (at E = 50 cm a joint is frozen through its clips
// and a level removes it: a claim about frozen joints).
inline std::vector<std::string> fixtureCharacters(const char* flag = nullptr) {
  return fixtureStrings("characters", "path", flag);
}

inline std::vector<std::string> fixtureClips() { return fixtureStrings("clips", nullptr, nullptr); }

// A test name from a fixture path: "X/BCN_Epileptic.X" -> "X_BCN_Epileptic_X".
inline std::string fixtureName(const ::testing::TestParamInfo<std::string>& info) {
  std::string name = info.param;
  std::replace_if(name.begin(), name.end(), [](unsigned char c) { return !std::isalnum(c); }, '_');
  return name;
}

} // namespace mlod::test
