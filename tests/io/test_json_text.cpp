// JSON text of names and texts that are not UTF-8 (issue 29, item 1): escaped as U+FFFD, never an
// exception; is_utf8 against the JSON library's own strict check on random bytes.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "mtcal/io/json/json.hpp"

namespace mtcal {
namespace {

const std::string kFffd = "\xEF\xBF\xBD";

TEST(JsonText, BytesThatAreNotUtf8BecomeReplacementCharacters) {
  Json j = {{"out", "out\xFF.csv"}, {"machine", "Fr\xE4se"}, {"ok", "\xC2\xB5m"}};
  const std::string text = json_text(j);
  EXPECT_EQ(text, "{\"out\":\"out" + kFffd + ".csv\",\"machine\":\"Fr" + kFffd + "se\",\"ok\":\"\xC2\xB5m\"}");
  const auto back = Json::parse(text);  // valid JSON, read by any parser
  EXPECT_EQ(back["out"], "out" + kFffd + ".csv");
  EXPECT_EQ(json_text(nlohmann::json("a\xFF")), "\"a" + kFffd + "\"");
  EXPECT_EQ(json_text(Json{{"k", 1}}, 2), "{\n  \"k\": 1\n}");
  // A truncated sequence is one replacement, the byte after it kept (maximal subparts).
  EXPECT_EQ(utf8_text("x\xE2\x82y"), "x" + kFffd + "y");
  EXPECT_EQ(utf8_text("\xFF\xFE"), kFffd + kFffd);
  EXPECT_EQ(utf8_text("plain"), "plain");
  // Keys too.
  EXPECT_EQ(json_text(Json{{"k\xFF", 1}}), "{\"k" + kFffd + "\":1}");
}

TEST(JsonText, IsUtf8AgreesWithTheJsonLibrary) {
  EXPECT_TRUE(is_utf8(""));
  EXPECT_TRUE(is_utf8("\xF0\x9F\x98\x80 \xE2\x82\xAC \xC2\xB5"));
  EXPECT_FALSE(is_utf8("\xC0\x80"));          // overlong NUL
  EXPECT_FALSE(is_utf8("\xED\xA0\x80"));      // a surrogate
  EXPECT_FALSE(is_utf8("\xF4\x90\x80\x80"));  // above U+10FFFF
  EXPECT_FALSE(is_utf8("\xE2\x82"));          // cut short at the end
  std::mt19937 rng(29);
  // Random bytes weighted towards the bytes of multi-byte sequences.
  const unsigned char pool[] = {'a', 0x7F, 0x80, 0x8F, 0x90, 0x9F, 0xA0, 0xBF, 0xC0, 0xC1, 0xC2, 0xDF,
                                0xE0, 0xE1, 0xEC, 0xED, 0xEE, 0xEF, 0xF0, 0xF1, 0xF3, 0xF4, 0xF5, 0xFF};
  int valid = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    std::string s;
    const int n = static_cast<int>(rng() % 6);
    for (int k = 0; k < n; ++k) s += static_cast<char>(pool[rng() % sizeof pool]);
    bool strict = true;
    try {
      (void)nlohmann::json(s).dump();
    } catch (const nlohmann::json::type_error&) {
      strict = false;
    }
    ASSERT_EQ(is_utf8(s), strict) << "bytes of length " << s.size() << " trial " << trial;
    valid += strict;
    const std::string fixed = utf8_text(s);
    ASSERT_TRUE(is_utf8(fixed));
    if (strict) {
      ASSERT_EQ(fixed, s);
    }
  }
  EXPECT_GT(valid, 1000);  // both kinds were tried
  EXPECT_LT(valid, 19000);
}

}  // namespace
}  // namespace mtcal
