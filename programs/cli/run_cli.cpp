// run_cli: parse_and_run (parse_and_run.cpp), and in an MPI job the end of every rank when one fails.
#include "hostio/process_group.hpp"
#include "programs/cli/commands.hpp"
#include "programs/cli/exit_code.hpp"

namespace lptn::cli {

int run_cli(CLI::App& app, int argc, char** argv) {
  const int code = parse_and_run(app, argc, argv);
  // In an MPI job one rank's failure must end the others, which would wait for it in a sum (an
  // outcome the command set as it finished, such as calibrate's 3, is every rank's and no failure).
  if (code != 0 && code != exit_code() && hostio::ProcessGroup::joined()) hostio::ProcessGroup::world().abort(code);
  return code;
}

}  // namespace lptn::cli
