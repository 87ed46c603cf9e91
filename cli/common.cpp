// seam CLI: pieces shared by the subcommands.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "common.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cerrno>
#include <locale>
#include <cstdlib>
#include <ostream>
#include <sstream>
#include <thread>

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

namespace seam_cli {

seam::KernelKind parse_kernel(const std::string& k) {
  if (k == "filtered") return seam::KernelKind::filtered;
  if (k == "float") return seam::KernelKind::float_;
  return seam::KernelKind::exact;
}

CLI::Option* add_number_option(CLI::App* app, const std::string& name, NumberText& value, const std::string& help) {
  return app->add_option(name, value.text, help)->type_name("NUMBER")->each([&value](const std::string&) {
    value.given = true;
  });
}

CLI::Option* add_bound_reach_option(CLI::App* app, NumberText& value) {
  return add_number_option(
      app, "--bound-reach", value,
      "How far from the faces the curves cross the quality stage holds faces to the angle bound where "
      "their input faces are below it, in steps of one face (integer, or auto); farther, such faces are "
      "held to their input face's smallest angle. 1 keeps the changes near the curves on anisotropic "
      "meshes (many more sections than points around), where the bound at every reach remeshes the "
      "mesh; faces at or above the bound in the input are held to it at any reach; 254 or more: no "
      "limit (default: auto, per mesh: no limit where at least half of its faces meet the bound, else 1)");
}

void read_bound_reach_option(const NumberText& value, long& bound_reach) {
  const double reach =
      number_option("--bound-reach", value, {0, 1e9, true, true, "faces"}, double(bound_reach), -1.0);
  bound_reach = long(reach);  // (-1: auto; the library takes 254 and more as no limit)
}

double number_option(const std::string& name, const NumberText& value, const NumberRange& range, double fallback,
                     double auto_value) {
  if (!value.given) return fallback;
  if (range.allow_auto && value.text == "auto") return auto_value;
  std::ostringstream expected;
  expected.imbue(std::locale::classic());
  expected << "must be " << (range.allow_auto ? "'auto' or " : "") << (range.integer ? "an integer" : "a finite number");
  if (range.max == HUGE_VAL) expected << " >= " << range.min;
  else expected << " from " << range.min << " to " << range.max;
  if (!range.note.empty()) expected << ", " << range.note;
  const auto refuse = [&](const std::string& why) {
    throw seam::InvalidInput(name + " " + value.text + ": " + why + " (" + expected.str() + ")");
  };
  // strtod in the "C" locale of a fresh process (the CLI never sets another): the whole text must
  // be the number, no blanks around it.
  const char* begin = value.text.c_str();
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(begin, &end);
  if (value.text.empty() || end == begin || *end != '\0' || std::isspace(static_cast<unsigned char>(value.text.front())))
    refuse("not a number");
  if (!std::isfinite(x)) refuse("not a finite number");
  if (range.integer && x != std::floor(x)) refuse("not an integer");
  if (!(x >= range.min && x <= range.max)) refuse("out of range");
  return x;
}

/// Same existing file, or the same normalised absolute path (an error computing either, e.g. a
/// permission problem, is not a match).
bool same_path(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec)) return true;
  // weakly_canonical leaves a relative path none of whose prefixes exists relative: make it absolute.
  const auto normal = [](const std::string& p, std::error_code& e) {
    const fs::path abs = fs::absolute(p, e);
    return e ? fs::path() : fs::weakly_canonical(abs, e);
  };
  std::error_code ea, eb;
  const fs::path ca = normal(a, ea), cb = normal(b, eb);
  return !ea && !eb && ca == cb;
}

void refuse_overwrite(const std::vector<std::string>& inputs, const std::vector<std::string>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const auto& out = outputs[i];
    if (out.empty()) continue;
    for (const auto& in : inputs)
      if (same_path(in, out))
        throw seam::InvalidInput(out + ": output path is the input " + in + " (refusing to overwrite an input)");
    for (std::size_t j = 0; j < i; ++j)
      if (!outputs[j].empty() && same_path(outputs[j], out))
        throw seam::InvalidInput(out + ": the same path is given for two outputs (" + outputs[j] + ")");
  }
}

std::vector<std::size_t> add_outputs(seam::OutputFiles& files, const std::vector<std::string>& paths) {
  std::vector<std::size_t> index;
  for (const auto& p : paths) index.push_back(p.empty() ? no_output : files.add(p));
  return index;
}

void handle_termination_signals() {
  sigset_t set;
  sigemptyset(&set);
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    // A signal ignored by the parent (SIGINT of a background job, nohup's SIGHUP) stays ignored.
    if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    sigaddset(&set, sig);
  }
  if (::pthread_sigmask(SIG_BLOCK, &set, nullptr) != 0) return;
  std::thread([set] {
    int sig = 0;
    while (::sigwait(&set, &sig) != 0) {
    }
    seam::remove_temporary_outputs();
    // End as the signal would have: the default action, unblocked in this thread.
    ::signal(sig, SIG_DFL);
    sigset_t one;
    sigemptyset(&one);
    sigaddset(&one, sig);
    ::pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
    ::raise(sig);
    ::_exit(128 + sig);
  }).detach();
}

void write_json(const nlohmann::json& j, std::ostream& out) {
  out << j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
}

std::string tolerance_text(double t) {
  char text[40];
  if (!(t > 0) || !std::isfinite(t)) {
    std::snprintf(text, sizeof text, "%.17g", t);
    return text;
  }
  for (int digits = 3; digits <= 17; ++digits) {
    const double unit = std::pow(10.0, std::floor(std::log10(t)) - digits + 1);
    std::snprintf(text, sizeof text, "%.*g", digits, std::ceil(t / unit) * unit);
    if (std::strtod(text, nullptr) >= t) return text;
  }
  std::snprintf(text, sizeof text, "%.17g", std::nextafter(t, HUGE_VAL));
  return text;
}

}  // namespace seam_cli
