// SHA-256 against the FIPS 180-2 / NIST test vectors, whole and fed in awkward pieces.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "lptn_testing/temp_dir.hpp"
#include "hostio/internal/sha256.hpp"
#include "hostio/sha256.hpp"

namespace lptn::hostio {
namespace {

std::string hash(const std::string& s) { return hostio::sha256_hex(s.data(), s.size()); }

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
  hostio::internal::Sha256 h;
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
  EXPECT_EQ(hostio::sha256_file(path), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_THROW(hostio::sha256_file(t.path() / "missing.csv"), std::runtime_error);
}

TEST(Sha256, FilesOverThreadsAreEachFilesHashInOrder) {
  testing::TempDir t;
  std::vector<std::filesystem::path> paths;
  for (int i = 0; i < 7; ++i) {
    paths.push_back(t.path() / ("cycle_" + std::to_string(i) + ".csv"));
    std::ofstream(paths.back(), std::ios::binary) << std::string(static_cast<std::size_t>(1000 * i), static_cast<char>('a' + i));
  }
  for (const int threads : {1, 2, 3, 16}) {
    const std::vector<std::string> hashes = hostio::sha256_files(paths, threads);
    ASSERT_EQ(hashes.size(), paths.size());
    for (std::size_t i = 0; i < paths.size(); ++i) EXPECT_EQ(hashes[i], hostio::sha256_file(paths[i])) << "threads " << threads;
  }
  EXPECT_TRUE(hostio::sha256_files({}, 2).empty());
  // Two unreadable files: the error names the first in order, whichever thread met it first.
  std::vector<std::filesystem::path> with_missing = paths;
  with_missing.insert(with_missing.begin() + 2, t.path() / "first_missing.csv");
  with_missing.push_back(t.path() / "second_missing.csv");
  for (const int threads : {1, 2, 5}) {
    try {
      hostio::sha256_files(with_missing, threads);
      ADD_FAILURE() << "no error on " << threads << " threads";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("first_missing.csv"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace lptn::hostio
