// app/cmd_bench.cpp: `pathview bench`: speed against error (see BENCHMARKS.md).
#include "app/commands.h"

#include "core/error.h"

namespace pv::app {

void add_bench_command(CLI::App& app) {
    CLI::App* cmd = app.add_subcommand("bench", "Measure speed against error (not yet available)");
    cmd->callback([] { throw Error("bench: not implemented yet"); });
}

}  // namespace pv::app
