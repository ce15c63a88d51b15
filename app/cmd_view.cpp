// app/cmd_view.cpp: `pathview view` (the default subcommand): the interactive viewer.
#include "app/commands.h"

#include "core/error.h"

namespace pv::app {

void add_view_command(CLI::App& app, CLI::App*& view_cmd) {
    auto o = std::make_shared<CommonOptions>();
    view_cmd = app.add_subcommand("view", "Open the interactive viewer (the default)");
    add_common_options(*view_cmd, *o);
    view_cmd->callback([o] {
        resolve_switches(*o);
        throw Error("the viewer is not built yet; use `pathview render`");
    });
}

}  // namespace pv::app
