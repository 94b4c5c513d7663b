// lptn-dbc-codegen: the C++ codecs of a DBC file, read by can/dbc (the reader `lptn replay --bus`
// uses), so the build and the run-time reading cannot disagree. Run by the build
// (lptn_generate_can_codecs in can/codecs/CMakeLists.txt).
//
// A refusal is one line `FILE:LINE: reason` on stderr, exit status 1 and no file written; what the
// reader reads past is `FILE:LINE: warning: reason`, after the header is written. --werror: the
// first warning refuses, as an error does (for the DBC files we write ourselves).
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "can/codegen/codecs.hpp"
#include "can/dbc/dbc.hpp"
#include "hostio/atomic_file.hpp"

namespace {

constexpr const char* kUsage =
    "usage: lptn-dbc-codegen --dbc FILE --node NODE [--namespace NS] --out HEADER [--werror]\n";
constexpr const char* kHelp =
    "Generate C++ CAN codecs (one header) from a DBC file.\n"
    "\n"
    "  --dbc FILE        the DBC file (UTF-8, or Latin-1 as Windows tools write it)\n"
    "  --node NODE       the node whose received and sent ids to list (Vector__XXX: none, a header for\n"
    "                    the whole bus; a signal outside its frame is then left out with a warning)\n"
    "  --namespace NS    C++ namespace of the generated code (default lptn::can)\n"
    "  --out HEADER      the header to write (whole or not at all)\n"
    "  --werror          a warning stops the generation as an error does (for DBC files we write)\n"
    "  --help            this text\n"
    "\n"
    "Exit status 0: written (warnings on stderr, FILE:LINE: warning: reason); 1: refused (one line,\n"
    "FILE:LINE: reason; nothing written); 2: wrong arguments.\n";

int usage_error(const std::string& problem) {
  std::fprintf(stderr, "%slptn-dbc-codegen: error: %s\n", kUsage, problem.c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string dbc_file, node, ns = "lptn::can", out;
  bool werror = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::fputs(kUsage, stdout);
      std::fputs("\n", stdout);
      std::fputs(kHelp, stdout);
      return 0;
    }
    if (arg == "--werror") {
      werror = true;
      continue;
    }
    std::string* value = arg == "--dbc" ? &dbc_file : arg == "--node" ? &node : arg == "--namespace" ? &ns : arg == "--out" ? &out : nullptr;
    if (!value) return usage_error("unrecognized argument " + arg);
    if (++i == argc) return usage_error("argument " + arg + ": expected one argument");
    *value = argv[i];
  }
  if (dbc_file.empty() || node.empty() || out.empty()) return usage_error("the following arguments are required: --dbc, --node, --out");
  if (!std::regex_match(ns, std::regex("[A-Za-z_]\\w*(::[A-Za-z_]\\w*)*")))
    return usage_error("--namespace '" + ns + "' is not a C++ namespace name");

  std::string header;
  std::vector<lptn::dbc::Warning> warnings;
  {
    std::ifstream probe(dbc_file, std::ios::binary);
    if (!probe) {
      std::fprintf(stderr, "%s:0: cannot read the file (%s)\n", dbc_file.c_str(), std::strerror(errno));
      return 1;
    }
  }
  try {
    const lptn::dbc::Database db = lptn::dbc::read(dbc_file, node);
    warnings = db.warnings;
    const std::string name = dbc_file.substr(dbc_file.find_last_of('/') + 1);
    header = lptn::codegen::codecs_header(db, {node, ns, name}, warnings);
  } catch (const lptn::dbc::Error& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  // The names' renames come after the reader's warnings; both in the order of their lines.
  std::stable_sort(warnings.begin(), warnings.end(), [](const auto& a, const auto& b) { return a.line < b.line; });
  if (werror && !warnings.empty()) {
    std::fprintf(stderr, "%s:%d: %s [--werror]\n", dbc_file.c_str(), warnings.front().line, warnings.front().reason.c_str());
    return 1;
  }
  try {
    const std::filesystem::path target(out);
    if (target.has_parent_path()) std::filesystem::create_directories(target.parent_path());
    lptn::hostio::write_file_atomically(target, header);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lptn-dbc-codegen: %s\n", e.what());
    return 1;
  }
  for (const auto& w : warnings) std::fprintf(stderr, "%s:%d: warning: %s\n", dbc_file.c_str(), w.line, w.reason.c_str());
  return 0;
}
