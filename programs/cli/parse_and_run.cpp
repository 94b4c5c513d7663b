// What every lptn program does with its command line and its failures (lptn, lptn-full, lptn-td3),
// without MPI: run_cli.cpp adds what an MPI job needs, for the programs that join one.
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>

#include "hostio/bad_input.hpp"
#include "programs/cli/commands.hpp"
#include "programs/cli/exit_code.hpp"

namespace lptn::cli {
namespace {
// Bad input of any kind: one line naming what was wrong, exit code 2.
int bad_input(const char* program, const std::exception& e) {
  std::fprintf(stderr, "%s: error: %s\n", program, e.what());
  return 2;
}
}  // namespace

namespace {
int& outcome_code() {
  static int code = 0;
  return code;
}
}  // namespace

void set_exit_code(int code) { outcome_code() = code; }
int exit_code() { return outcome_code(); }

std::vector<std::string>& invocation() {
  static std::vector<std::string> args;
  return args;
}

int parse_and_run(CLI::App& app, int argc, char** argv) {
  invocation().assign(argv, argv + argc);
  const std::string program = app.get_name();
  // CLI11 would only say that a subcommand is required; name the word it did not know.
  std::string known;
  bool is_known = false;
  for (const CLI::App* sub : app.get_subcommands({})) {
    known += (known.empty() ? "" : ", ") + sub->get_name();
    is_known = is_known || (argc > 1 && sub->get_name() == argv[1]);
  }
  if (argc > 1 && argv[1][0] != '-' && !is_known) {
    std::fprintf(stderr, "%s: error: unknown subcommand '%s' (known: %s)\n", program.c_str(), argv[1], known.c_str());
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "%s: error: %s (see --help)\n", program.c_str(), e.what());
    return 2;
  } catch (const hostio::BadInput& e) {
    return bad_input(program.c_str(), e);
  } catch (const std::invalid_argument& e) {
    return bad_input(program.c_str(), e);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: failed: %s\n", program.c_str(), e.what());
    return 1;
  }
  return exit_code();
}

}  // namespace lptn::cli
