// Names from files made valid UTF-8 (core/utf8.h): a Latin-1 joint name made --json, glTF
// and report exports throw nlohmann's type_error 316.

#include "core/utf8.h"

#include <gtest/gtest.h>

namespace mlod {
namespace {

// Guards the table of well-formed sequences: ASCII, 2- to 4-byte forms are valid; a lone
// Latin-1 byte, a truncated sequence, an overlong form and a surrogate are not.
TEST(Utf8, WellFormedSequencesOnly) {
  EXPECT_TRUE(isValidUtf8("Hips"));
  EXPECT_TRUE(isValidUtf8("caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80"));
  EXPECT_TRUE(isValidUtf8(""));
  EXPECT_FALSE(isValidUtf8("caf\xE9"));          // Latin-1 é
  EXPECT_FALSE(isValidUtf8("\xE2\x82"));         // cut short
  EXPECT_FALSE(isValidUtf8("\xC0\xAF"));         // overlong '/'
  EXPECT_FALSE(isValidUtf8("\xED\xA0\x80"));     // a UTF-16 surrogate
  EXPECT_FALSE(isValidUtf8("\xF4\x90\x80\x80")); // past U+10FFFF
}

// Guards the replacement: each bad byte becomes U+FFFD, good text is kept as it is.
TEST(Utf8, BadBytesBecomeReplacementCharacters) {
  EXPECT_EQ(validUtf8("caf\xE9"), "caf\xEF\xBF\xBD");
  EXPECT_EQ(validUtf8("\xE9t\xE9"), "\xEF\xBF\xBDt\xEF\xBF\xBD");
  EXPECT_EQ(validUtf8("caf\xC3\xA9"), "caf\xC3\xA9");
  EXPECT_TRUE(isValidUtf8(validUtf8("\xFF\xFE\xC3")));
}

} // namespace
} // namespace mlod
