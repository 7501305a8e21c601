// io::Printable and io::NulByteLine (params/io/csv.h): how the readers quote a file's text in a
// message (issue 50 finding 11: a binary file's bytes reached the terminal).
#include <gtest/gtest.h>

#include <string>

#include "params/io/csv.h"

namespace scw::io {
namespace {

TEST(Printable, KeepsTextAndUtf8) {
  EXPECT_EQ(Printable("vx_mps"), "vx_mps");
  EXPECT_EQ(Printable("\xCE\xB2 [deg]"), "\xCE\xB2 [deg]");              // β
  EXPECT_EQ(Printable("\xF0\x9F\x9A\x97 car"), "\xF0\x9F\x9A\x97 car");  // a 4-byte character
  EXPECT_EQ(Printable(""), "");
}

TEST(Printable, EscapesWhatATerminalWouldActOn) {
  EXPECT_EQ(Printable("\x1B[2J"), "\\x1B[2J");
  EXPECT_EQ(Printable(std::string("a\0b", 3)), "a\\x00b");
  EXPECT_EQ(Printable("\t\r\n\x7F"), "\\x09\\x0D\\x0A\\x7F");
  // Bytes of no UTF-8 character: a lone continuation byte, a C1 introducer, a cut sequence,
  // an overlong form and a surrogate.
  EXPECT_EQ(Printable("\x80"), "\\x80");
  EXPECT_EQ(Printable("\x9B"
                      "31m"),
            "\\x9B31m");
  EXPECT_EQ(Printable("\xCE"), "\\xCE");
  EXPECT_EQ(Printable("\xC0\xAF"), "\\xC0\\xAF");
  EXPECT_EQ(Printable("\xED\xA0\x80"), "\\xED\\xA0\\x80");
}

TEST(Printable, CutsAfterMaxBytesWithoutSplittingACharacter) {
  EXPECT_EQ(Printable(std::string(50, 'a')), std::string(40, 'a') + "...");
  EXPECT_EQ(Printable("abcdef", 6), "abcdef");
  EXPECT_EQ(Printable("abc\xCE\xB2", 4), "abc...");
}

TEST(NulByteLine, LineOfTheFirstNul) {
  EXPECT_EQ(NulByteLine("a,b\n1,2\n"), 0u);
  EXPECT_EQ(NulByteLine(std::string("\0", 1)), 1u);
  EXPECT_EQ(NulByteLine(std::string("a\nb\n\0c\0", 7)), 3u);
}

}  // namespace
}  // namespace scw::io
