// `vcmm report OUTDIR [--title T]` — the validation figures (SVG, PDF, PNG) and the
// self-contained HTML report of a `vcmm validate` / `vcmm demo` output directory, drawn by
// python/vcmm_report.py (docs/report.md). The command only finds and runs the script:
//   script: <prefix>/share/vcmm/vcmm_report.py beside an installed binary, else
//           python/vcmm_report.py of the source tree this binary was built from;
//   Python: the first of /usr/bin/python3 and every python3 on PATH that imports matplotlib
//           and numpy; none → says what to install (exit 3: a program it needs is missing).
// The script's exit code is returned (0 ok, 1 internal error, 2 usage, 3 invalid input).
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"

extern char** environ;

namespace vcmm::cli {
namespace {

namespace fs = std::filesystem;

/// Runs argv[0] (an absolute path) with argv; quiet: standard output and error to /dev/null.
/// Returns its exit code, or -1 when it cannot be started or does not exit normally.
int run_program(const std::vector<std::string>& args, bool quiet) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (quiet) {
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  }
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}

/// /usr/bin/python3, then python3 in every directory of PATH (in order, without repeats).
std::vector<fs::path> python_candidates() {
  std::vector<fs::path> out{"/usr/bin/python3"};
  const char* path = std::getenv("PATH");
  std::string rest = path ? path : "";
  while (!rest.empty()) {
    const auto colon = rest.find(':');
    const std::string dir = rest.substr(0, colon);
    rest = colon == std::string::npos ? "" : rest.substr(colon + 1);
    if (dir.empty()) continue;
    const fs::path p = fs::path(dir) / "python3";
    bool seen = false;
    for (const auto& q : out) seen = seen || q == p;
    if (!seen) out.push_back(p);
  }
  return out;
}

/// The installed copy beside the binary, else the source tree's (VCMM_SOURCE_DIR).
std::vector<fs::path> script_candidates() {
  std::vector<fs::path> out;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) out.push_back(exe.parent_path().parent_path() / "share" / "vcmm" / "vcmm_report.py");
  out.push_back(fs::path(VCMM_SOURCE_DIR) / "python" / "vcmm_report.py");
  return out;
}

struct ReportOptions {
  std::string outdir;
  std::string title;
};

int run_report(const ReportOptions& o) {
  fs::path script;
  for (const auto& s : script_candidates())
    if (script.empty() && fs::is_regular_file(s)) script = s;
  if (script.empty()) {
    std::cerr << "vcmm report: python/vcmm_report.py not found (looked for";
    for (const auto& s : script_candidates()) std::cerr << " " << s.string();
    std::cerr << "); reinstall vcmm or run the script from the source tree\n";
    return kInvalidInput;
  }
  std::vector<fs::path> tried;
  for (const auto& python : python_candidates()) {
    if (access(python.c_str(), X_OK) != 0) continue;
    tried.push_back(python);
    if (run_program({python.string(), "-c", "import matplotlib, numpy"}, true) != 0) continue;
    std::vector<std::string> args{python.string(), script.string(), o.outdir};
    if (!o.title.empty()) args.insert(args.end(), {"--title", o.title});
    const int rc = run_program(args, false);
    if (rc < 0) {
      std::cerr << "vcmm report: could not run " << python.string() << " " << script.string()
                << "\n";
      return kFailure;
    }
    return rc;
  }
  std::cerr << "vcmm report: no Python 3 with matplotlib and numpy found (tried";
  for (const auto& p : tried) std::cerr << " " << p.string();
  if (tried.empty()) std::cerr << " /usr/bin/python3 and python3 on PATH: none exists";
  std::cerr << "); install them: apt-get install python3-matplotlib python3-numpy\n";
  return kInvalidInput;
}

}  // namespace

void add_report_command(CLI::App& app, int* exit_code) {
  auto o = std::make_shared<ReportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "report", "figures (SVG, PDF, PNG) and a self-contained HTML report of a validate/demo "
                "output directory (python/vcmm_report.py with matplotlib)");
  cmd->add_option("OUTDIR", o->outdir, "output directory of vcmm validate or vcmm demo")
      ->required();
  cmd->add_option("--title", o->title, "report title");
  cmd->callback([o, exit_code] { *exit_code = run_report(*o); });
}

}  // namespace vcmm::cli
