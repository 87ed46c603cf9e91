// seam CLI: pieces shared by the subcommands.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/embed.h>
#include <seam/improve.h>
#include <seam/io.h>

#include "report.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace seam_cli {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// A subcommand: its CLI11 app and what runs it once parsed.
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

Command add_embed_command(CLI::App& app);
Command add_pair_command(CLI::App& app);
Command add_check_command(CLI::App& app);
Command add_check_embed_command(CLI::App& app);
Command add_textile_command(CLI::App& app);
Command add_mesh_command(CLI::App& app);
Command add_resolve_command(CLI::App& app);

seam::KernelKind parse_kernel(const std::string& k);

/// A numeric option, kept as the text given until checked by number_option() before any work
/// (CLI11 would accept "nan", "inf" and negative values for a double).
struct NumberText {
  std::string text;
  bool given = false;
};

/// Registers `--name VALUE` for a NumberText.
CLI::Option* add_number_option(CLI::App* app, const std::string& name, NumberText& value, const std::string& help);

/// What a numeric option accepts: a finite number in [min, max] (both included), or the word
/// "auto" when `auto_value` is set (the documented automatic default, which the library spells as
/// a negative number: a negative number from the user is refused).
struct NumberRange {
  double min = 0;
  double max = HUGE_VAL;
  bool integer = false;
  bool allow_auto = false;
  std::string note;  ///< for the message, e.g. "degrees"

  static NumberRange non_negative() { return {}; }
  static NumberRange non_negative_or_auto() { return {0, HUGE_VAL, false, true, ""}; }
  static NumberRange between(double lo, double hi, std::string note) { return {lo, hi, false, false, std::move(note)}; }
  static NumberRange integer_between(double lo, double hi, std::string note) {
    return {lo, hi, true, false, std::move(note)};
  }
};

/// The value of a numeric option: `fallback` when not given, `auto_value` for "auto", else the
/// number, which must be finite and within `range`. Throws InvalidInput, one line naming the
/// option and the value: "--snap-tol -1: out of range (must be 'auto' or a finite number >= 0)".
double number_option(const std::string& name, const NumberText& value, const NumberRange& range, double fallback,
                     double auto_value = -1.0);

/// `--bound-reach N` of the commands that run the quality stage (ImproveOptions::bound_reach):
/// registers it, and reads it into `bound_reach` (left as it is when not given; "auto": -1).
CLI::Option* add_bound_reach_option(CLI::App* app, NumberText& value);
void read_bound_reach_option(const NumberText& value, long& bound_reach);

/// Whether two paths name the same file.
bool same_path(const std::string& a, const std::string& b);

/// Refuses an output path that names one of the inputs (never overwrite an input), or another
/// output (one would silently replace the other).
void refuse_overwrite(const std::vector<std::string>& inputs, const std::vector<std::string>& outputs);

/// Checks the output paths before any work and creates their temporary files (see
/// seam::OutputFiles), in the order given, which is the order they are renamed in (meshes, then
/// curves, then the report, which comes last). Empty paths are skipped: their index is npos.
std::vector<std::size_t> add_outputs(seam::OutputFiles& files, const std::vector<std::string>& paths);

constexpr std::size_t no_output = static_cast<std::size_t>(-1);

/// Handles SIGINT, SIGTERM and SIGHUP (those not ignored when the process started) in a thread
/// of their own: it removes every temporary output (seam::remove_temporary_outputs(), which
/// waits for a commit in progress), then ends the process by the same signal. Call first in
/// main(), before any other thread exists (they inherit the blocked signals).
void handle_termination_signals();

/// A tolerance for the user to pass to `seam check --tol`: the shortest decimal of 3 or more
/// significant digits that is not below `t` (rounding to nearest could make the check fail).
std::string tolerance_text(double t);

/// Writes JSON to a stream; file names need not be UTF-8 (invalid bytes are replaced).
void write_json(const nlohmann::json& j, std::ostream& out);

}  // namespace seam_cli
