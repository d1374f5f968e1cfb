// Runs the built `squint` command line for the end-to-end tests and captures its exit code,
// standard output and standard error (separately, through private temporary files, so that
// tests running in parallel under ctest -j never read each other's output).
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace squint::test {

struct CliResult {
  int code = -1;    // exit status; -1 when the process did not exit normally
  std::string out;  // standard output
  std::string err;  // standard error
  std::string all() const { return out + err; }
};

inline std::string ReadWholeFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// `args` is appended to the binary's path and run by the shell.
inline CliResult RunSquint(const std::string& args) {
  namespace fs = std::filesystem;
  static std::atomic<int> counter{0};
  const std::string stem = "squint_cli_" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
  const fs::path out_path = fs::temp_directory_path() / (stem + ".out");
  const fs::path err_path = fs::temp_directory_path() / (stem + ".err");
  const std::string cmd =
      std::string(SQUINT_BINARY) + " " + args + " > " + out_path.string() + " 2> " + err_path.string();
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.code = (status != -1 && WIFEXITED(status)) ? WEXITSTATUS(status) : -1;
  r.out = ReadWholeFile(out_path);
  r.err = ReadWholeFile(err_path);
  std::error_code ec;
  fs::remove(out_path, ec);
  fs::remove(err_path, ec);
  return r;
}

}  // namespace squint::test
