// lptn-bus-codegen: the firmware's glue to a converter's bus (fw::BusDecoder) from a bus map, read by
// can/bus, the reader `lptn replay --bus` uses. Run by the build (lptn_generate_bus_glue in
// can/codecs/CMakeLists.txt). A map the reader refuses: one line `FILE:LINE: reason` on stderr, exit
// status 1, no file written.
#include <cstdio>
#include <filesystem>
#include <string>

#include "can/bus/bus_map.hpp"
#include "can/codegen/bus_glue.hpp"
#include "hostio/atomic_file.hpp"

namespace {

constexpr const char* kUsage =
    "usage: lptn-bus-codegen --bus BUS_TOML (--print-dbc | --codecs HEADER --codec-namespace NS [--namespace NS] --out HEADER)\n";
constexpr const char* kHelp =
    "Generate the firmware's glue to a converter's bus from its bus map (bus.toml).\n"
    "\n"
    "  --bus FILE              the bus map; the DBC it names is read beside it\n"
    "  --print-dbc             print the map's DBC file and exit\n"
    "  --codecs HEADER         the include path of the codecs generated from the map's DBC (lptn-dbc-codegen)\n"
    "  --codec-namespace NS    their namespace\n"
    "  --namespace NS          namespace of the glue (default lptn::bus)\n"
    "  --out HEADER            the header to write (whole or not at all)\n"
    "  --help                  this text\n"
    "\n"
    "Exit status 0: done (warnings on stderr); 1: the map or its DBC refused (one line, FILE:LINE:\n"
    "reason; nothing written); 2: wrong arguments.\n";

int usage_error(const std::string& problem) {
  std::fprintf(stderr, "%slptn-bus-codegen: error: %s\n", kUsage, problem.c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string bus, codecs, codec_ns, ns = "lptn::bus", out;
  bool print_dbc = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::fputs(kUsage, stdout);
      std::fputs("\n", stdout);
      std::fputs(kHelp, stdout);
      return 0;
    }
    if (arg == "--print-dbc") {
      print_dbc = true;
      continue;
    }
    std::string* value = arg == "--bus"               ? &bus
                         : arg == "--codecs"          ? &codecs
                         : arg == "--codec-namespace" ? &codec_ns
                         : arg == "--namespace"       ? &ns
                         : arg == "--out"             ? &out
                                                      : nullptr;
    if (!value) return usage_error("unrecognized argument " + arg);
    if (++i == argc) return usage_error("argument " + arg + ": expected one argument");
    *value = argv[i];
  }
  if (bus.empty()) return usage_error("--bus is required");
  std::unique_ptr<lptn::bus::BusMap> map;
  try {
    map = lptn::bus::BusMap::read(bus);
  } catch (const std::exception& e) {  // MapError, or dbc::Error from its DBC: one line each
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  for (const std::string& w : map->warnings()) std::fprintf(stderr, "%s\n", w.c_str());
  if (print_dbc) {
    std::printf("%s\n", map->database().path.c_str());
    return 0;
  }
  if (out.empty() || codecs.empty() || codec_ns.empty()) return usage_error("--out, --codecs and --codec-namespace are required");
  try {
    const std::string name = std::filesystem::path(bus).filename().string();
    const std::string header = lptn::codegen::bus_glue_header(*map, {name, codecs, codec_ns, ns});
    const std::filesystem::path target(out);
    if (target.has_parent_path()) std::filesystem::create_directories(target.parent_path());
    lptn::hostio::write_file_atomically(target, header);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
