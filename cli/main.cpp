// seam: the command-line tool.
//
// Exit codes: 0 success; 2 bad input or usage (one line on stderr: "seam: FILE: problem");
// 3 internal failure ("seam: internal error: ..."). Outputs are written to a temporary file and
// renamed, and a failed run removes the outputs it already wrote, so it leaves no output; an
// output path equal to an input or to another output is refused.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include "common.h"

#include <CGAL/exceptions.h>

#include <iostream>

int main(int argc, char** argv) {
  CLI::App app{"seam: embed boundary curves exactly into triangle tow surface meshes, so that two "
               "interpenetrating tows share the curve vertex for vertex and edge for edge."};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Print help for every subcommand");
  const std::vector<seam_cli::Command> commands = {seam_cli::add_embed_command(app), seam_cli::add_pair_command(app),
                                                    seam_cli::add_check_command(app),
                                                    seam_cli::add_textile_command(app)};

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
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
