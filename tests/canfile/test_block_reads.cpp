// The host's faster ways through a log are the firmware's: BlockLineReader gives LineReader's lines,
// numbers and too-long verdicts on every awkward file, and the candump writer's lines are
// format_candump_line's.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "hostio/line_reader.hpp"
#include "lptn/firmware/candump_line.hpp"
#include "can/canfile/can_log.hpp"
#include "can/canfile/internal/block_line_reader.hpp"

namespace lptn::canfile {
namespace {

struct Seen {
  int status;
  std::string line;
  std::size_t number;
  bool operator==(const Seen&) const = default;
};

template <class Reader>
std::vector<Seen> read_all(const std::string& content) {
  std::FILE* f = std::tmpfile();
  std::fwrite(content.data(), 1, content.size(), f);
  std::rewind(f);
  Reader reader(f);
  std::vector<Seen> seen;
  std::string_view line;
  for (hostio::LineReader::Status s; (s = reader.next(line)) != hostio::LineReader::Status::end;)
    seen.push_back({static_cast<int>(s), s == hostio::LineReader::Status::line ? std::string(line) : "", reader.line_number()});
  std::fclose(f);
  return seen;
}

TEST(BlockLineReader, GivesLineReadersLinesOnEveryAwkwardFile) {
  const std::string l512(512, 'x'), l513(513, 'y');
  std::vector<std::string> files = {
      "",
      "\n",
      "\n\n\n",
      "one",
      "one\ntwo",
      "one\ntwo\n",
      "crlf\r\nline\r\n",
      std::string("nul\0byte\n", 9),
      l512 + "\n" + l513 + "\nafter\n",
      l513,
      l512,
      "a\n" + std::string(3000000, 'z') + "\nb\n",             // a line across many blocks
      "a\n" + std::string(3000000, 'z'),                       // ... that ends the file
      std::string((256 << 10) - 1, 'q') + "\n" + "tail\n",     // a newline at a block's last byte
      std::string(256 << 10, 'q') + "\n" + "tail\n",
  };
  // Lines of every length around the block's size, so that every cut falls somewhere new.
  std::mt19937 g(3);
  std::uniform_int_distribution<int> len(0, 600);
  std::string many;
  while (many.size() < (3u << 20)) many += std::string(static_cast<std::size_t>(len(g)), 'a' + static_cast<char>(g() % 26)) + '\n';
  files.push_back(many);
  for (std::size_t i = 0; i < files.size(); ++i)
    EXPECT_TRUE(read_all<BlockLineReader>(files[i]) == read_all<hostio::LineReader>(files[i])) << "file " << i;
}

TEST(CandumpWriter, WritesFormatCandumpLinesLines) {
  std::mt19937_64 g(11);
  for (const std::string& interface : std::vector<std::string>{"can0", "vcan12", std::string(15, 'i')}) {
    const auto writer = make_log_writer(LogFormat::candump, interface);
    std::string expected;
    for (int i = 0; i < 20000; ++i) {
      fw::CanFrame f;
      const int kind = static_cast<int>(g() % 8);
      f.extended = kind >= 4;
      f.id = static_cast<std::uint32_t>(g() % (f.extended ? 0x20000000u : 0x800u));
      if (kind == 0) f.id = 0;
      if (kind == 7) f.id = 0x1FFFFFFFu;
      f.remote = kind == 3;
      f.error = kind == 6 && g() % 4 == 0;
      f.fd = kind == 5 && g() % 4 == 0;
      f.len = static_cast<std::uint8_t>(f.fd ? g() % 65 : g() % 9);
      for (unsigned b = 0; b < f.len; ++b) f.data[b] = static_cast<std::uint8_t>(g());
      const fw::TimeUs t = i % 100 == 0 ? static_cast<fw::TimeUs>(g() % 10000000000000000ULL)
                                        : static_cast<fw::TimeUs>(1700000000000000LL + i * 1234);
      writer->add(t, f);
      char line[200];
      const std::size_t n = fw::format_candump_line(line, sizeof line, t, interface, f);
      ASSERT_GT(n, 0u);
      expected.append(line, n).push_back('\n');
    }
    EXPECT_TRUE(writer->finish() == expected) << interface;
  }
}

}  // namespace
}  // namespace lptn::canfile
