#include "spheremap/text.hpp"

#include <gtest/gtest.h>

#include <string>

namespace spheremap {
namespace {

const std::string kFFFD = "\xEF\xBF\xBD";

TEST(ValidUtf8, WellFormedTextComesBackUnchanged) {
  for (const std::string& text : {std::string(), std::string("CA"), std::string("Å², 1.4 Å"),
                                  std::string("\xF0\x9F\x99\x82"), std::string("a\0b", 3)}) {
    EXPECT_TRUE(is_valid_utf8(text)) << text;
    EXPECT_EQ(valid_utf8(text), text);
  }
}

TEST(ValidUtf8, EveryIllFormedSequenceBecomesReplacementCharacters) {
  EXPECT_EQ(valid_utf8("caf\xE9.pdb"), "caf" + kFFFD + ".pdb");              // ISO 8859-1 é
  EXPECT_EQ(valid_utf8("\xC0\xAF"), kFFFD + kFFFD);                          // overlong '/'
  EXPECT_EQ(valid_utf8("\xED\xA0\x80"), kFFFD + kFFFD + kFFFD);              // a surrogate
  EXPECT_EQ(valid_utf8("\xF4\x90\x80\x80"), kFFFD + kFFFD + kFFFD + kFFFD);  // above U+10FFFF
  EXPECT_EQ(valid_utf8("\xE2\x82"), kFFFD);                                  // cut short: one maximal subpart
  EXPECT_EQ(valid_utf8("\xE2\x82x"), kFFFD + "x");
  EXPECT_EQ(valid_utf8("\xFF\xFE"), kFFFD + kFFFD);
  EXPECT_EQ(valid_utf8("\x80"), kFFFD);  // a lone continuation byte
}

TEST(ValidUtf8, ItsOutputIsValidAndApplyingItTwiceChangesNothing) {
  std::string all;
  for (int b = 0; b < 256; ++b) all += static_cast<char>(b), all += static_cast<char>(255 - b);
  const std::string once = valid_utf8(all);
  EXPECT_TRUE(is_valid_utf8(once));
  EXPECT_EQ(valid_utf8(once), once);
}

}  // namespace
}  // namespace spheremap
