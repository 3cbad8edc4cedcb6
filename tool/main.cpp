// The `tear` command line: the app, its subcommands, and the one place where exceptions become
// exit codes (0 ok, 1 usage, 2 bad input, 3 runtime failure, 4 interrupted, 5 meshes differ) and one-line messages.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>

#include <unistd.h>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "farm.h"
#include "tear/error.h"

namespace {

int fail(int code, const std::string& message) {
  std::cerr << "tear: " << tear::cli::one_line(message) << std::endl;
  return code;
}

#if defined(__SANITIZE_ADDRESS__)
#define TEAR_CHECK_LEAKS_AT_EXIT 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define TEAR_CHECK_LEAKS_AT_EXIT 1
#endif
#endif

/// Ends a failed command with `code` once what it printed is out. By then every scope of the
/// command has been left (its threads joined, its files closed or removed); what is left to run
/// are the libraries' handlers at exit, which have nothing to add and must not turn the documented
/// code into another. A sanitized build returns instead, so that LeakSanitizer's check at exit runs.
int end_failed(int code) {
#if !defined(TEAR_CHECK_LEAKS_AT_EXIT)
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  std::_Exit(code);
#endif
  return code;
}

/// The help command to suggest after a usage error: that of the subcommand being parsed, if any.
std::string help_hint(const CLI::App& app) {
  std::string command = "tear";
  for (const CLI::App* sub : app.get_subcommands()) command += " " + sub->get_name();
  return " (see '" + command + " --help')";
}

/// A good neighbour on a shared node (docs/cli.md, *Threads*): waiting OpenMP threads sleep
/// (`OMP_WAIT_POLICY=PASSIVE`) rather than spin, and a Slurm job's CPUs bound the threads
/// (`SLURM_CPUS_PER_TASK` as `OMP_NUM_THREADS`); what the environment sets already is kept. The
/// OpenMP runtime reads its environment once, when it is loaded, before `main` (and before any
/// constructor of the program's own), so when something is to be set the program sets it and
/// starts itself again, as the same process (`execv`); if that fails it goes on as it is.
void set_openmp_environment(char** argv) {
  bool again = false;
  if (!std::getenv("OMP_WAIT_POLICY")) {
    setenv("OMP_WAIT_POLICY", "PASSIVE", 1);
    again = true;
  }
  const char* slurm = std::getenv("SLURM_CPUS_PER_TASK");
  if (slurm && *slurm && std::strspn(slurm, "0123456789") == std::strlen(slurm) && !std::getenv("OMP_NUM_THREADS")) {
    setenv("OMP_NUM_THREADS", slurm, 1);
    again = true;
  }
  if (again) execv("/proc/self/exe", argv);
}

}  // namespace

int main(int argc, char** argv) {
  set_openmp_environment(argv);
  tear::cli::install_stop_handlers();  // SIGTERM and SIGINT end in exit 4 from here on
  CLI::App app{"Cut and tear triangle cloth meshes on the GPU (or the CPU).", "tear"};
  app.set_version_flag("--version", "tear " TEAR_VERSION, "Print the version and exit");
  app.require_subcommand(1);
  app.footer(
      "Exit codes: 0 ok, 1 usage error, 2 bad input, 3 runtime failure, 4 stopped (resumable), 5 meshes differ (tear "
      "diff). Run 'tear COMMAND --help' for "
      "the options of a command; docs/cli.md describes them all.");

  tear::cli::add_info_command(app);
  tear::cli::add_run_command(app);
  tear::cli::add_validate_command(app);
  tear::cli::add_bench_command(app);
  tear::cli::add_demo_command(app);
  tear::cli::add_diff_command(app);
  tear::cli::add_batch_command(app);

  try {
    app.parse(argc, argv);  // the chosen subcommand runs inside, as its callback
    return 0;
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);  // --help, --version
    return end_failed(fail(1, e.what() + help_hint(app)));
  } catch (const tear::cli::ExitCode& e) {
    return end_failed(e.code);  // the command has said what it had to
  } catch (...) {
    const tear::cli::Failure failure = tear::cli::current_failure();
    return end_failed(fail(failure.code, failure.message));
  }
}
