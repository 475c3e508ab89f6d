// The spheremap command line: a thin layer over the library (see include/spheremap/pipeline/).
// Each subcommand lives in its own file (commands.hpp); this file registers and dispatches them.
#include <iostream>

#include "blas_kernels.hpp"
#include "commands.hpp"
#include "spheremap/error.hpp"
#include "spheremap/text.hpp"

int main(int argc, char** argv) {
  spheremap::cli::use_blas_kernels_for_this_cpu(argv);
  CLI::App app{
      "spheremap: maps closed genus-0 surfaces onto the unit sphere, one-to-one and certified\n"
      "(Rahi & Sharp, 'Mapping Complicated Surfaces onto a Sphere', with the cases the paper leaves out).\n"
      "Exit codes: 0 certified map written; 1 bad command line or unreadable input; 2 mesh refused\n"
      "(open, non-manifold, several components, genus != 0; nothing written); 3 map written but NOT certified;\n"
      "4 internal error."};
  app.set_version_flag("--version", "spheremap 0.1.0");
  app.require_subcommand(1);

  const std::vector<spheremap::cli::Command> commands = {
      spheremap::cli::add_map_command(app),      spheremap::cli::add_surface_command(app),
      spheremap::cli::add_generate_command(app), spheremap::cli::add_batch_command(app),
      spheremap::cli::add_table_command(app),    spheremap::cli::add_render_command(app),
      spheremap::cli::add_view_command(app),     spheremap::cli::add_locate_command(app),
  };

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are "errors" with code 0; every real command-line mistake exits 1.
    const int printed = app.exit(e);
    return printed == 0 ? 0 : static_cast<int>(spheremap::ExitCode::kUsage);
  }

  try {
    for (const auto& command : commands)
      if (*command.app) return command.run();
    return static_cast<int>(spheremap::ExitCode::kUsage);
  } catch (const spheremap::Error& e) {
    std::cerr << "spheremap: error: " << spheremap::valid_utf8(e.what()) << "\n";
    return static_cast<int>(e.code());
  } catch (const std::exception& e) {
    std::cerr << "spheremap: internal error: " << spheremap::valid_utf8(e.what()) << "\n";
    return 4;
  }
}
