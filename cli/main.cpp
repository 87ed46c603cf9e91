// seam: the command-line tool.
//
// Exit codes: 0 success; 2 bad input or usage (one line on stderr: "seam: FILE: problem");
// 3 internal failure ("seam: internal error: ..."). Every option and output path is checked
// before any work; every output goes to a temporary file in its directory, created at that
// check, and all are renamed together at the end (seam::OutputFiles): a failure or SIGINT /
// SIGTERM / SIGHUP before that leaves the old outputs untouched and no temporary file. An output
// path equal to an input or to another output is refused.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include "common.h"

#include <CGAL/exceptions.h>

#include <iostream>

int main(int argc, char** argv) {
  seam_cli::handle_termination_signals();  // before any other thread exists
  CLI::App app{"seam: embed boundary curves exactly into triangle tow surface meshes, so that two "
               "interpenetrating tows share the curve vertex for vertex and edge for edge."};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Print help for every subcommand");
  const std::vector<seam_cli::Command> commands = {seam_cli::add_embed_command(app), seam_cli::add_pair_command(app),
                                                    seam_cli::add_check_command(app),
                                                    seam_cli::add_check_embed_command(app),
                                                    seam_cli::add_textile_command(app),
                                                    seam_cli::add_mesh_command(app),
                                                    seam_cli::add_resolve_command(app)};

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    // A usage error: one line, as for every other error.
    std::string what = e.what();
    for (char& c : what)
      if (c == '\n' || c == '\r') c = ' ';
    std::cerr << "seam: " << what << " (see seam --help)\n";
    return 2;
  }

  try {
    for (const auto& command : commands)
      if (*command.app) return command.run();
    return 2;
  } catch (const seam::InvalidInput& e) {
    std::cerr << "seam: " << e.what() << "\n";
    return 2;
  } catch (const seam::IOError& e) {
    std::cerr << "seam: " << e.what() << "\n";
    return 2;
  } catch (const seam::InternalError& e) {
    std::cerr << "seam: internal error: " << e.what() << "\n";
    return 3;
  } catch (const CGAL::Failure_exception& e) {
    std::cerr << "seam: internal error: CGAL: " << e.message() << " (" << e.expression() << ")\n";
    return 3;
  } catch (const std::bad_alloc&) {
    std::cerr << "seam: internal error: out of memory\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "seam: internal error: " << e.what() << "\n";
    return 3;
  }
}
