// `tear batch SHOTS.json`: a list of shots, each the arguments of one `tear run`, run one after the
// other in this process. Each shot writes, reports and fails as if it had run alone.
#include <climits>
#include <filesystem>
#include <future>
#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "commands.h"
#include "run_command.h"
#include "tear/device.h"
#include "tear/error.h"

namespace tear::cli {

namespace {

struct BatchOptions {
  std::string shots_path;
  std::string device = "auto";
  std::string progress = "auto";
  int writer_threads = 0;
  bool verbose = false;
};

/// A shot's entry that is not what `tear run` would take: a usage error, as the same mistake on
/// `tear run`'s command line is.
Error shot_error(const std::string& file, const std::string& key, const std::string& what) {
  return Error(ErrorKind::usage, file + ": " + key + ": " + what);
}

std::string type_of(const nlohmann::json& value) {
  if (value.is_number_integer()) return "an integer";
  if (value.is_number()) return "a number";
  return value.type_name();
}

std::string get_string(const nlohmann::json& value, const std::string& file, const std::string& key) {
  if (!value.is_string()) throw shot_error(file, key, "expected a string, got " + type_of(value));
  return value.get<std::string>();
}

int get_int(const nlohmann::json& value, const std::string& file, const std::string& key, long low, long high,
            const std::string& expected) {
  if (!value.is_number_integer() || value.get<long long>() < low || value.get<long long>() > high)
    throw shot_error(file, key, "expected " + expected + ", got " + value.dump());
  return static_cast<int>(value.get<long long>());
}

double get_number(const nlohmann::json& value, const std::string& file, const std::string& key, bool zero_allowed,
                  const std::string& expected) {
  if (!value.is_number()) throw shot_error(file, key, "expected " + expected + ", got " + value.dump());
  const double number = value.get<double>();
  if (!std::isfinite(number) || number < 0 || (!zero_allowed && number == 0))
    throw shot_error(file, key, "expected " + expected + ", got " + value.dump());
  return number;
}

bool get_bool(const nlohmann::json& value, const std::string& file, const std::string& key) {
  if (!value.is_boolean()) throw shot_error(file, key, "expected true or false, got " + type_of(value));
  return value.get<bool>();
}

/// The options of `tear run` that shot `index` of the list gives (docs/cli.md, `tear batch`).
RunCommandOptions shot_options(const nlohmann::json& shot, std::size_t index, const BatchOptions& batch) {
  const std::string& file = batch.shots_path;
  const std::string at = "[" + std::to_string(index) + "]";
  if (!shot.is_object()) throw shot_error(file, at, "expected an object, got " + type_of(shot));
  RunCommandOptions options;
  options.device = batch.device;
  options.verbose = batch.verbose;
  options.farm.progress = batch.progress;
  options.farm.writer_threads = batch.writer_threads;
  for (const char* required : {"mesh", "script", "output"})
    if (!shot.contains(required)) throw shot_error(file, at + "." + required, "missing (a shot needs mesh, script and output)");
  for (const auto& [name, value] : shot.items()) {
    const std::string key = at + "." + name;
    if (name == "mesh") options.mesh_path = get_string(value, file, key);
    else if (name == "script") options.script_path = get_string(value, file, key);
    else if (name == "output") options.output_pattern = get_string(value, file, key);
    else if (name == "frames") options.frames = get_int(value, file, key, 1, INT_MAX, "an integer >= 1");
    else if (name == "start_frame") options.start_frame = get_int(value, file, key, 0, INT_MAX, "an integer >= 0");
    else if (name == "report") options.report_path = get_string(value, file, key);
    else if (name == "up_axis") {
      options.up_axis = get_string(value, file, key);
      if (options.up_axis != "Y" && options.up_axis != "Z" && options.up_axis != "y" && options.up_axis != "z")
        throw shot_error(file, key, "expected \"Y\" or \"Z\", got " + value.dump());
      options.usd_metadata_given = true;
    } else if (name == "meters_per_unit") {
      options.meters_per_unit = get_number(value, file, key, false, "a finite number > 0");
      options.usd_metadata_given = true;
    } else if (name == "device") options.device = get_string(value, file, key);
    else if (name == "mesh_name") options.read.mesh_name = get_string(value, file, key);
    else if (name == "weld_tolerance") options.read.weld_tolerance = get_number(value, file, key, true, "a finite number >= 0");
    else if (name == "no_weld") options.read.weld = !get_bool(value, file, key);
    else if (name == "checkpoint") options.farm.checkpoint_path = get_string(value, file, key);
    else if (name == "checkpoint_every") options.farm.checkpoint_every = get_int(value, file, key, 1, 1000000, "an integer in 1..1000000");
    else if (name == "resume") options.farm.resume = get_bool(value, file, key);
    else if (name == "writer_threads") options.farm.writer_threads = get_int(value, file, key, 0, 256, "an integer in 0..256");
    else if (name == "verbose") options.verbose = get_bool(value, file, key);
    else if (name == "strict") options.strict = get_bool(value, file, key);
    else
      throw shot_error(file, key,
                       "unknown key (a shot takes mesh, script, output, frames, start_frame, report, up_axis, "
                       "meters_per_unit, device, mesh_name, weld_tolerance, no_weld, checkpoint, checkpoint_every, "
                       "resume, writer_threads, verbose, strict)");
  }
  return options;
}

/// The folder `path` names or lies in, whole (links resolved as far as the path exists).
std::filesystem::path folder_of(const std::string& path, bool is_folder) {
  std::error_code error;
  const std::filesystem::path whole = std::filesystem::weakly_canonical(std::filesystem::absolute(path), error);
  if (error) return {};
  return is_folder ? whole : whole.parent_path();
}

bool within(const std::filesystem::path& inner, const std::filesystem::path& outer) {
  auto o = outer.begin();
  for (auto i = inner.begin(); o != outer.end(); ++i, ++o)
    if (i == inner.end() || *i != *o) return false;
  return true;
}

/// Whether `next`'s mesh may be read while `running` runs: when it lies in none of the folders
/// `running` writes into (its frames', report's and checkpoint's, and below them), so that a shot
/// reading a file an earlier shot wrote reads it once written.
bool reads_apart(const RunCommandOptions& next, const RunCommandOptions& running) {
  const std::filesystem::path mesh_folder = folder_of(next.mesh_path, false);
  if (mesh_folder.empty()) return false;
  // The frames' folder: the pattern up to its first placeholder.
  const std::string& pattern = running.output_pattern;
  const std::string fixed = pattern.substr(0, pattern.find_first_of("#{"));
  std::vector<std::filesystem::path> written{folder_of(fixed, !fixed.empty() && fixed.back() == '/')};
  if (fixed.empty()) written.back() = folder_of(".", true);
  for (const std::string* file : {&running.report_path, &running.farm.checkpoint_path})
    if (!file->empty()) written.push_back(folder_of(*file, false));
  for (const std::filesystem::path& folder : written)
    if (folder.empty() || within(mesh_folder, folder)) return false;
  return true;
}

/// The list of shots; anything but a readable JSON array is bad input of the batch as a whole.
nlohmann::json read_shots(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw input_error(path, "cannot open the shot list");
  std::stringstream text;
  text << in.rdbuf();
  nlohmann::json shots;
  try {
    shots = nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::parse_error& e) {
    throw input_error(path, std::string("not valid JSON: ") + e.what());
  }
  if (!shots.is_array()) throw input_error(path, "expected a list of shots, got " + type_of(shots));
  if (shots.empty()) throw input_error(path, "the list holds no shot");
  return shots;
}

/// Shot after shot allocates and frees arrays of the same sizes. By default glibc gives blocks of
/// a few megabytes back to the system as they are freed and the next shot faults every page of
/// them in again (a sixth of a 1M-face shot's time): a batch keeps them for its next shot, in one
/// arena, so that each shot's new writer threads take the blocks the last shot's freed.
void keep_freed_memory() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // the most glibc takes: larger blocks are still mapped each time
  mallopt(M_TRIM_THRESHOLD, INT_MAX);
  mallopt(M_ARENA_MAX, 1);
#endif
}

void run_batch(const BatchOptions& batch) {
  keep_freed_memory();
  // The batch's device is checked before its list is read, as `tear run` checks its own.
  select_device(batch.device);
  const nlohmann::json shots = read_shots(batch.shots_path);
  const std::size_t count = shots.size();
  int batch_code = 0;
  std::vector<std::string> failed;
  // While a shot runs, the next shot's mesh is read beside it (when it lies apart from what the
  // shot writes); what reading found or threw is said at the next shot's turn, as alone.
  std::future<MeshRead> ahead;
  for (std::size_t i = 0; i < count; ++i) {
    int code = 0;
    try {
      RunCommandOptions options = shot_options(shots[i], i, batch);
      // Read ahead, or read by the shot itself (its report's `input_ms` then holds the reading).
      std::future<MeshRead> mesh = std::move(ahead);
      if (mesh.valid()) options.mesh_read = &mesh;
      if (i + 1 < count) {
        try {
          const RunCommandOptions next = shot_options(shots[i + 1], i + 1, batch);
          // Read on as many threads as the batch's --threads allows (a new thread starts at OpenMP's).
          const int threads = cpu_threads();
          if (reads_apart(next, options))
            ahead = std::async(std::launch::async, [threads, path = next.mesh_path, read = next.read] {
              set_cpu_threads(threads);
              return read_mesh_quietly(path, read);
            });
        } catch (...) {
          // the next shot's entry is wrong: said at its turn
        }
      }
      run_run(options);
    } catch (...) {
      const Failure failure = current_failure();
      code = failure.code;
      std::cerr << "tear: " << failure.message << std::endl;
    }
    if (batch.verbose)
      std::cout << "shot " << i + 1 << '/' << count << ": " << (code == 0 ? "ok" : "failed, exit " + std::to_string(code))
                << std::endl;
    if (code == 0) continue;
    failed.push_back("[" + std::to_string(i) + "] (exit " + std::to_string(code) + ")");
    if (code == static_cast<int>(ErrorKind::interrupted)) {
      batch_code = code;
      break;  // the shots after it are not started
    }
    if (code > batch_code) batch_code = code;
  }
  if (batch_code == 0) return;
  std::string list;
  for (const std::string& f : failed) list += (list.empty() ? "" : ", ") + f;
  std::cerr << "tear: " << batch.shots_path << ": " << failed.size() << " of " << count
            << (count == 1 ? " shot" : " shots") << " failed: " << list
            << (batch_code == static_cast<int>(ErrorKind::interrupted) ? "; stopped, the shots after it were not run"
                                                                       : "")
            << std::endl;
  throw ExitCode{batch_code};
}

}  // namespace

void add_batch_command(CLI::App& app) {
  auto options = std::make_shared<BatchOptions>();
  CLI::App* command =
      app.add_subcommand("batch", "Run a list of shots (each the arguments of one 'tear run') one after the other");
  command->footer(
      "SHOTS.json is a list of objects: {\"mesh\": ..., \"script\": ..., \"output\": ...} and optionally frames, "
      "start_frame, report, up_axis, meters_per_unit, device, mesh_name, weld_tolerance, no_weld, checkpoint, "
      "checkpoint_every, resume, writer_threads, verbose, strict (docs/cli.md). Each shot writes, reports and fails as "
      "'tear run' would alone; a failed shot does not stop the others. Exit codes: 0 every shot ok, else the "
      "largest exit code of the failed shots (1 usage, 2 bad input, 3 runtime failure), 4 when stopped by "
      "SIGTERM/SIGINT (the shots after it are not run), 2 when SHOTS.json itself is unusable.");
  command->add_option("SHOTS", options->shots_path, "The list of shots (JSON)")->required()->type_name("");
  add_device_option(*command, options->device);
  command
      ->add_option("--progress", options->progress, "Progress of each shot on standard error, as 'tear run'")
      ->type_name("auto|bar|lines|none")
      ->check(CLI::IsMember({"auto", "bar", "lines", "none"}))
      ->capture_default_str();
  command
      ->add_option("--writer-threads", options->writer_threads, "Writer threads of each shot, as 'tear run'")
      ->type_name("N")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
  command->add_flag("-v,--verbose", options->verbose,
                    "Print each shot's frames as 'tear run -v' does, and one line per shot: 'shot 2/3: ok'");
  command->callback([options] { run_batch(*options); });
}

}  // namespace tear::cli
