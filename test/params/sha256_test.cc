// Manifest digests: SHA-256 exactly as `sha256sum` computes it (FIPS 180-4 test vectors, every
// padding boundary against the system tool when it is installed).
#include "params/io/sha256.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace scw::io {
namespace {

TEST(Sha256Test, StandardVectors) {
  EXPECT_EQ(Sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(Sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(Sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(Sha256Hex(std::string(1000000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

std::string SystemSha256(const std::string& bytes) {
  const auto path = std::filesystem::temp_directory_path() / "scw_sha256_test.bin";
  std::ofstream(path, std::ios::binary) << bytes;
  FILE* p = ::popen(("sha256sum " + path.string() + " 2>/dev/null").c_str(), "r");
  std::string out;
  if (p) {
    char buf[128];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    ::pclose(p);
  }
  std::filesystem::remove(path);
  return out.size() >= 64 ? out.substr(0, 64) : "";
}

TEST(Sha256Test, EqualsSha256sumAcrossEveryPaddingBoundary) {
  if (SystemSha256("x").empty()) GTEST_SKIP() << "sha256sum not available";
  for (std::size_t n : {0u, 1u, 55u, 56u, 57u, 63u, 64u, 65u, 119u, 120u, 127u, 128u, 1000u}) {
    std::string bytes(n, '\0');
    for (std::size_t i = 0; i < n; ++i) bytes[i] = static_cast<char>((i * 131u + 7u) & 0xff);
    EXPECT_EQ(Sha256Hex(bytes), SystemSha256(bytes)) << n << " bytes";
  }
}

}  // namespace
}  // namespace scw::io
