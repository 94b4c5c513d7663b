// SHA-256 against the FIPS 180-2 / NIST test vectors, whole and fed in awkward pieces.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "lptn_testing/temp_dir.hpp"
#include "hostio/internal/sha256.hpp"
#include "hostio/sha256.hpp"

namespace lptn {
namespace {

std::string hash(const std::string& s) { return sha256_hex(s.data(), s.size()); }

TEST(Sha256, StandardVectors) {
  EXPECT_EQ(hash(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(hash("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  // 448 bits: the padding no longer fits the block, a second one is needed.
  EXPECT_EQ(hash("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(hash("abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmnhijklmnoijklmnopjklmnopqklmnopqrlmnopqrs"
                 "mnopqrstnopqrstu"),
            "cf5b16a778af8380036ce59e7b0492370b249b11e8f07a51afac45037afee9d1");
  EXPECT_EQ(hash(std::string(1000000, 'a')), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, PiecesGiveTheSameHashAsTheWhole) {
  const std::string a(1000000, 'a');
  internal::Sha256 h;
  std::size_t at = 0, piece = 1;
  while (at < a.size()) {
    const std::size_t n = std::min(piece, a.size() - at);
    h.update(a.data() + at, n);
    at += n;
    piece = piece * 3 % 157 + 1;  // sizes that straddle block boundaries every way
  }
  EXPECT_EQ(h.hex(), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, File) {
  testing::TempDir t;
  const auto path = t.path() / "abc.csv";
  std::ofstream(path, std::ios::binary) << "abc";
  EXPECT_EQ(sha256_file(path), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_THROW(sha256_file(t.path() / "missing.csv"), std::runtime_error);
}

}  // namespace
}  // namespace lptn
