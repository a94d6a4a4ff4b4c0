// tests/support/cli_run.h — runs the `vcmm` executable for the CLI contract tests.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace vcmm::test {

struct CliRun {
  int exit_code = -1;
  std::string out;
  std::string err;
};

/// A scratch directory unique to this test process (created on first use).
inline std::filesystem::path scratch_dir() {
  static const std::filesystem::path dir = [] {
    std::filesystem::path d = std::filesystem::temp_directory_path() /
                              ("vcmm_cli_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// Runs `exe args` through the shell, standard input from `stdin_file` when given, and
/// returns its exit code and captured standard output and error.
inline CliRun run_command(const std::string& exe, const std::string& args,
                          const std::string& stdin_file = "") {
  const auto out = scratch_dir() / "stdout.txt";
  const auto err = scratch_dir() / "stderr.txt";
  std::string cmd = "'" + exe + "' " + args + " >'" + out.string() + "' 2>'" + err.string() + "'";
  if (!stdin_file.empty()) cmd += " <'" + stdin_file + "'";
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

}  // namespace vcmm::test
