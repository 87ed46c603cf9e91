// seam CLI: pieces shared by the subcommands.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/embed.h>
#include <seam/improve.h>
#include <seam/io.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
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
Command add_textile_command(CLI::App& app);

seam::KernelKind parse_kernel(const std::string& k);

/// Whether two paths name the same file.
bool same_path(const std::string& a, const std::string& b);

/// Refuses an output path that names one of the inputs (never overwrite an input), or another
/// output (one would silently replace the other).
void refuse_overwrite(const std::vector<std::string>& inputs, const std::vector<std::string>& outputs);

/// Runs `write` (which writes outputs and records each written path in `written`); if it throws,
/// removes what it wrote, so that a failed run leaves no output, and rethrows.
void write_all_or_nothing(const std::function<void(std::vector<std::string>& written)>& write);

/// The JSON of an embedding's statistics (the keys documented in the README).
nlohmann::json stats_json(const seam::EmbedStats& s);

/// The JSON of the quality stage's report (the keys documented in the README): counts of edits
/// and refusals, the band's angles before and after, and each face left below the bound with its
/// cause (mesh names from `mesh_names`).
nlohmann::json improve_json(const seam::ImproveStats& s, bool done, const std::vector<std::string>& mesh_names);

/// Writes JSON atomically; file names need not be UTF-8 (invalid bytes are replaced).
void write_json(const nlohmann::json& j, const std::string& path);

}  // namespace seam_cli
