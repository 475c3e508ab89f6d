// The subcommands of the spheremap CLI, one file each; main.cpp only registers and dispatches them.
#pragma once

#include <functional>
#include <memory>

#include <CLI/CLI.hpp>

#include "options.hpp"

namespace spheremap::cli {

/// A registered subcommand and what runs it after parsing; `run` returns the process exit code and may
/// throw spheremap::Error (main turns it into a message and the error's exit code).
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

/// Registers the subcommand whose name, description, options and work live in a `State`: State::kName,
/// State::kDescription, State::add(CLI::App*) registers the options into its members, State::run() runs
/// after parsing.
template <typename State>
Command make_command(CLI::App& parent) {
  auto state = std::make_shared<State>();
  CLI::App* app = parent.add_subcommand(State::kName, State::kDescription);
  state->add(app);
  return {app, [state] { return state->run(); }};
}

Command add_map_command(CLI::App& app);
Command add_surface_command(CLI::App& app);
Command add_generate_command(CLI::App& app);
Command add_batch_command(CLI::App& app);
Command add_table_command(CLI::App& app);
Command add_render_command(CLI::App& app);
Command add_view_command(CLI::App& app);
Command add_locate_command(CLI::App& app);

}  // namespace spheremap::cli
