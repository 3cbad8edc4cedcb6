// tear's Python module, `tear._tear`: the library's meshes, scripts, runs and cloth, through
// nanobind. The Python package (python/tear/__init__.py) adds the keyword-argument API on top; the
// arrays a frame hands out are read-only NumPy views of its host buffers, never copies.
#include <dlfcn.h>

#include <cmath>
#include <csignal>
#include <cstring>
#include <memory>
#include <new>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>
#include <nanobind/stl/array.h>

#include "tear/tear.h"

namespace nb = nanobind;
using namespace nb::literals;

namespace {

// ---------------------------------------------------------------------------------------------
// Errors: one Python class per exit code of the CLI, the message the CLI prints after "tear: ".

// Indexed by exit code (0 unused); references held for the life of the process, so that nothing is
// released after the interpreter is gone.
PyObject* error_classes[5] = {};

std::string one_line(std::string message) {
  for (char& c : message)
    if (c == '\n' || c == '\r') c = ' ';
  while (!message.empty() && message.back() == ' ') message.pop_back();
  return message;
}

void raise_as(int code, const std::string& message) {
  PyObject* cls = code >= 1 && code <= 4 && error_classes[code] ? error_classes[code] : PyExc_RuntimeError;
  PyErr_SetString(cls, one_line(message).c_str());
}

void translate(const std::exception_ptr& p, void*) {
  try {
    std::rethrow_exception(p);
  } catch (const tear::Error& e) {
    raise_as(e.exit_code(), e.what());
  } catch (const std::bad_alloc&) {
    raise_as(3, "out of memory");
  }
}

// ---------------------------------------------------------------------------------------------
// Meshes and frames: a host mesh, whose arrays Python sees without a copy.

struct PyMesh {
  tear::Mesh mesh;
  std::string source;        // the file it was read from, for messages and output checks
  tear::ReadOptions read;    // how it was read (a checkpoint's digest names them)
  std::vector<tear::index_t> ids;  // node ids: node i is id i (docs/identity.md)
  double fps = 24;           // time codes per second of a USD layer it is written to

  void fill_ids() {
    ids.resize(static_cast<std::size_t>(mesh.node_count()));
    std::iota(ids.begin(), ids.end(), 0);
  }
};

struct PyFrame : PyMesh {
  int number = 0;        // the frame's number in outputs (start_frame + script frame - 1)
  int script_frame = 0;  // 1..frames, as the script counts
  int cut_count = 0;
  tear::index_t tear_events = 0;
  double torn_length = 0;
};

template <typename T>
using Array = nb::ndarray<nb::numpy, const T, nb::c_contig>;

/// A read-only NumPy array over `data`, kept alive by the Python object of `owner`.
template <typename T>
nb::object view(const PyMesh& owner, const std::vector<T>& data, std::initializer_list<size_t> shape) {
  nb::object self = nb::find(&owner);
  static const T empty{};
  const T* ptr = data.empty() ? &empty : data.data();
  return nb::cast(Array<T>(ptr, shape, self));
}

template <typename T>
nb::object view_or_none(const PyMesh& owner, const std::vector<T>& data, std::initializer_list<size_t> shape) {
  if (data.empty()) return nb::none();
  return view(owner, data, shape);
}

size_t nodes(const PyMesh& m) { return static_cast<size_t>(m.mesh.node_count()); }
size_t faces(const PyMesh& m) { return static_cast<size_t>(m.mesh.face_count()); }

/// The frame's file (or USD layer) at `path`, a pattern whose placeholders take `number`, through
/// the sink `tear run` would use for it.
void write_frame(const PyMesh& m, const std::string& path, int number, std::optional<std::string> up_axis,
                 std::optional<double> meters_per_unit) {
  const tear::FramePattern pattern(path);
  pattern.check(1, number);
  if ((up_axis || meters_per_unit) && !tear::is_usd_path(path))
    throw tear::Error(tear::ErrorKind::usage,
                      "--up-axis and --meters-per-unit apply to USD output only (.usda, .usd), not to '" + path + "'");
  std::unique_ptr<tear::FrameSink> sink;
  if (tear::is_usd_path(path)) {
    tear::UsdLayerOptions usd;
    usd.frames_per_second = m.fps;
    if (up_axis) usd.up_axis = tear::parse_up_axis(*up_axis);
    if (meters_per_unit) usd.meters_per_unit = *meters_per_unit;
    sink = std::make_unique<tear::UsdLayer>(pattern, usd);
  } else {
    sink = std::make_unique<tear::FrameFiles>(pattern);
  }
  nb::gil_scoped_release release;
  sink->write(number, m.mesh);
  sink->finish();
}

nb::object dlpack(nb::handle self_handle, nb::kwargs kwargs) {
  PyMesh& m = nb::cast<PyMesh&>(self_handle);
  // DLPack has no read-only flag before its version 1, so the capsule is of a writable tensor (a
  // writable NumPy view, whose own `__dlpack__` makes it); the buffer is the frame's, to be read only.
  nb::ndarray<nb::numpy, float, nb::c_contig> points(m.mesh.node_pos.empty() ? nullptr : m.mesh.node_pos.data(),
                                          {nodes(m), 3}, self_handle);
  nb::object array = nb::cast(points);
  return array.attr("__dlpack__")(**kwargs);
}

tear::Device pick_device(const std::string& spec) { return tear::select_device(spec); }

// ---------------------------------------------------------------------------------------------
// Scripts.

struct PyScript {
  tear::CutScript script;
};

// ---------------------------------------------------------------------------------------------
// A run frame by frame: each `next` runs one frame of the script on the cloth and hands its mesh
// over as `tear run` writes it.

struct FrameIterator {
  std::shared_ptr<const PyMesh> input;
  tear::CutScript script;
  tear::Device device = tear::Device::cpu;
  int start_frame = 1;
  int frame_count = 0;
  int next_frame = 1;
  std::unique_ptr<tear::Cloth> cloth;
};

nb::object next_frame(FrameIterator& it) {
  if (it.next_frame > it.frame_count || !it.cloth) {
    it.cloth.reset();  // the cloth's memory goes as soon as the run is over
    throw nb::stop_iteration();
  }
  auto frame = std::make_unique<PyFrame>();
  // A frame that fails (a diverged simulation) ends the run: the next `next` stops.
  struct EndOnError {
    FrameIterator& it;
    bool ok = false;
    ~EndOnError() {
      if (!ok) it.cloth.reset();
    }
  } end_on_error{it};
  {
    nb::gil_scoped_release release;
    const int f = it.next_frame;
    tear::run_cuts(
        *it.cloth, it.script, f,
        [&](const tear::FrameResult& result, const tear::Cloth& cloth) {
          // As `run_to_files` hands a frame to its writer: a moved cloth that came with normals is
          // written with normals of its moved positions.
          const bool normals = result.simulated && cloth.has_corner_normals();
          frame->mesh = cloth.mesh_later(!normals).take();
          if (normals) frame->mesh.corner_normal = tear::area_weighted_corner_normals(frame->mesh);
          frame->script_frame = result.frame;
          frame->cut_count = result.cut_count;
          frame->tear_events = result.tear_events;
          frame->torn_length = result.torn_length;
        },
        f);
    frame->number = it.start_frame + f - 1;
    frame->fps = it.script.simulation ? it.script.simulation->fps : 24.0;
    frame->source = it.input->source;
    frame->fill_ids();
    ++it.next_frame;
  }
  end_on_error.ok = true;
  return nb::cast(frame.release(), nb::rv_policy::take_ownership);
}

// ---------------------------------------------------------------------------------------------
// Whole runs to files, stopped by SIGINT or SIGTERM after a whole frame as `tear run` is.

volatile std::sig_atomic_t stop_requested = 0;
extern "C" void request_stop(int) { stop_requested = 1; }

struct StopHandlers {
  struct sigaction old_int {}, old_term {};
  StopHandlers() {
    stop_requested = 0;
    struct sigaction action {};
    action.sa_handler = request_stop;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    sigaction(SIGINT, &action, &old_int);
    sigaction(SIGTERM, &action, &old_term);
  }
  ~StopHandlers() {
    sigaction(SIGINT, &old_int, nullptr);
    sigaction(SIGTERM, &old_term, nullptr);
  }
};

std::string result_options(const tear::ReadOptions& read) {
  return "mesh-name=" + read.mesh_name + ";weld-tolerance=" + std::to_string(read.weld_tolerance) +
         ";weld=" + (read.weld ? "1" : "0");
}

// ---------------------------------------------------------------------------------------------
// A cloth held on a backend, cut and stepped from Python.

struct PyCloth {
  std::unique_ptr<tear::Cloth> cloth;
  bool has_uv = false;
  std::string source;
  std::optional<tear::SimulationOptions> simulation;
  int frames_stepped = 0;
};

/// Where a cloth's arrays live, as DLPack says it: (kDLCUDA, its GPU) or (kDLCPU, 0).
std::pair<int, int> dlpack_device(const PyCloth& c) {
  if (c.cloth->device() == tear::Device::cuda)
    return {static_cast<int>(nb::device::cuda::value), std::max(0, tear::current_gpu())};
  return {static_cast<int>(nb::device::cpu::value), 0};
}

/// The cloth's positions where the backend keeps them, as a DLPack capsule (which PyTorch, CuPy and
/// NumPy take without a copy; `tear.Cloth.positions` wraps it in the DLPack protocol).
nb::ndarray<float, nb::ndim<2>, nb::c_contig> cloth_positions(nb::handle self) {
  PyCloth& c = nb::cast<PyCloth&>(self);
  const auto [device_type, device_id] = dlpack_device(c);
  const float* data = nullptr;
  {
    nb::gil_scoped_release release;
    data = c.cloth->node_pos_data();
  }
  // The owner is the Python cloth: an array a consumer took keeps it alive (not its buffer, which
  // the next cut or step may move: docs/python.md says so). DLPack before its version 1 has no
  // read-only flag, so the array is writable; it is documented to be read.
  return nb::ndarray<float, nb::ndim<2>, nb::c_contig>(
      const_cast<float*>(data), {static_cast<std::size_t>(c.cloth->node_count()), 3}, self, {}, nb::dtype<float>(),
      device_type, device_id);
}

/// Positions from the host or, for a cloth on the GPU, from the same GPU's memory.
void set_cloth_positions(PyCloth& c, const nb::ndarray<const float, nb::ndim<2>, nb::c_contig>& points) {
  const std::size_t nodes = static_cast<std::size_t>(c.cloth->node_count());
  if (points.shape(0) != nodes || points.shape(1) != 3)
    throw tear::Error(tear::ErrorKind::usage, "points: expected shape (" + std::to_string(nodes) + ", 3), got (" +
                                                  std::to_string(points.shape(0)) + ", " +
                                                  std::to_string(points.shape(1)) + ")");
  const bool gpu = c.cloth->device() == tear::Device::cuda;
  if (points.device_type() == nb::device::cuda::value) {
    if (!gpu)
      throw tear::Error(tear::ErrorKind::usage, "points: a GPU array for a cloth on the CPU; copy it to the host first");
    if (points.device_id() != tear::current_gpu())
      throw tear::Error(tear::ErrorKind::usage, "points: an array on GPU " + std::to_string(points.device_id()) +
                                                    " for a cloth on GPU " + std::to_string(tear::current_gpu()));
  } else if (points.device_type() != nb::device::cpu::value) {
    throw tear::Error(tear::ErrorKind::usage, "points: expected an array in host or CUDA memory");
  }
  nb::gil_scoped_release release;
  c.cloth->copy_node_pos_from(points.data());
}

tear::CutSpace parse_space(const std::string& space) {
  if (space == "uv") return tear::CutSpace::uv;
  if (space == "rest-xy") return tear::CutSpace::rest_xy;
  if (space == "rest-xz") return tear::CutSpace::rest_xz;
  if (space == "rest-yz") return tear::CutSpace::rest_yz;
  throw tear::Error(tear::ErrorKind::usage,
                    "space: expected \"uv\", \"rest-xy\", \"rest-xz\" or \"rest-yz\", got \"" + space + "\"");
}

/// Refuses a libtear.so built from other headers than this module (one found first through
/// LD_LIBRARY_PATH, an older build's): its types would not be the module's, and the first script
/// or mesh handed across would corrupt memory (tear/layout.h). An ImportError instead.
void check_library_layout() {
  if (tear::library_layout_digest() == tear::layout_digest_here()) return;
  Dl_info info{};
  const auto fn = &tear::cuda_available;  // a function of libtear.so alone (the digest may be interposed)
  void* address = nullptr;
  static_assert(sizeof(fn) == sizeof(address));
  std::memcpy(&address, &fn, sizeof(address));
  const std::string library = dladdr(address, &info) && info.dli_fname ? info.dli_fname : "libtear.so";
  throw std::runtime_error("tear: " + library +
                           " was built from other headers than this module; rebuild both together, or check "
                           "that LD_LIBRARY_PATH does not lead to another build's libtear.so");
}

}  // namespace

NB_MODULE(_tear, m) {
  check_library_layout();
  m.doc() = "tear's library, bound with nanobind (use the `tear` package, not this module)";
  m.attr("__version__") = TEAR_VERSION;
  nb::register_exception_translator(translate);
  // Arrays another library took through DLPack may still hold a frame when the interpreter exits,
  // after nanobind's own teardown: not a leak, and no message for it. (The test suite checks that
  // memory stays flat over a long run instead.)
  nb::set_leak_warnings(false);

  m.def("_set_error_classes", [](nb::object usage, nb::object input, nb::object runtime, nb::object interrupted) {
    nb::object classes[] = {usage, input, runtime, interrupted};
    for (int code = 1; code <= 4; ++code) error_classes[code] = classes[code - 1].release().ptr();
  });
  m.def("_cuda_available", &tear::cuda_available);

  nb::class_<PyMesh>(m, "Mesh")
      .def_prop_ro("node_count", [](const PyMesh& s) { return s.mesh.node_count(); })
      .def_prop_ro("face_count", [](const PyMesh& s) { return s.mesh.face_count(); })
      .def_prop_ro("source", [](const PyMesh& s) { return s.source; })
      .def_prop_ro("points", [](const PyMesh& s) { return view(s, s.mesh.node_pos, {nodes(s), 3}); })
      .def_prop_ro("faces", [](const PyMesh& s) { return view(s, s.mesh.face_nodes, {faces(s), 3}); })
      .def_prop_ro("uvs", [](const PyMesh& s) { return view_or_none(s, s.mesh.corner_uv, {faces(s), 3, 2}); })
      .def_prop_ro("normals",
                   [](const PyMesh& s) { return view_or_none(s, s.mesh.corner_normal, {faces(s), 3, 3}); })
      .def_prop_ro("velocities", [](const PyMesh& s) { return view_or_none(s, s.mesh.node_vel, {nodes(s), 3}); })
      .def_prop_ro("ids", [](const PyMesh& s) { return view(s, s.ids, {nodes(s)}); })
      .def_prop_ro("origins", [](const PyMesh& s) { return view_or_none(s, s.mesh.node_origin_face, {nodes(s)}); })
      .def_prop_ro("origin_weights",
                   [](const PyMesh& s) { return view_or_none(s, s.mesh.node_origin_bary, {nodes(s), 2}); })
      .def_prop_ro("torn_edges", [](const PyMesh& s) {
        return view(s, s.mesh.torn_edge_nodes, {s.mesh.torn_edge_nodes.size() / 2, 2});
      })
      .def("_write", [](const PyMesh& s, const std::string& path, int number, std::optional<std::string> up_axis,
                        std::optional<double> mpu) { write_frame(s, path, number, up_axis, mpu); },
           "path"_a, "number"_a, "up_axis"_a.none(), "meters_per_unit"_a.none())
      .def("__dlpack__", &dlpack)
      .def("__dlpack_device__", [](const PyMesh&) { return std::make_pair(1, 0); });

  nb::class_<PyFrame, PyMesh>(m, "Frame")
      .def_ro("number", &PyFrame::number)
      .def_ro("script_frame", &PyFrame::script_frame)
      .def_ro("cut_count", &PyFrame::cut_count)
      .def_ro("tear_events", &PyFrame::tear_events)
      .def_ro("torn_length", &PyFrame::torn_length);

  m.def("_read_mesh", [](const std::string& path, double weld_tolerance, const std::string& mesh_name, bool weld,
                         const std::string& device_spec) {
    const tear::Device device = pick_device(device_spec);
    auto out = std::make_unique<PyMesh>();
    out->read.mesh_name = mesh_name;
    out->read.weld_tolerance = weld_tolerance;
    out->read.weld = weld;
    out->source = path;
    {
      nb::gil_scoped_release release;
      out->mesh = tear::read_mesh(path, out->read);
      // What `tear run` and `tear info` check before anything else (tool/common.cpp).
      const tear::MeshReport report = tear::check_indices(out->mesh, device);
      if (!report.readable()) {
        auto plural = [](std::int64_t n, const char* one, const char* many) {
          return std::to_string(n) + " " + (n == 1 ? one : many);
        };
        throw tear::input_error(path, report.describe() + " (the mesh has " +
                                          plural(out->mesh.node_count(), "node", "nodes") + " and " +
                                          plural(out->mesh.face_count(), "face", "faces") + ")");
      }
    }
    out->fill_ids();
    return out.release();
  }, nb::rv_policy::take_ownership);

  nb::class_<PyScript>(m, "Script")
      .def_prop_ro("frames", [](const PyScript& s) { return s.script.frames; })
      .def_prop_ro("snap", [](const PyScript& s) { return s.script.snap; })
      .def_prop_ro("version", [](const PyScript& s) { return s.script.version; })
      .def_prop_ro("path", [](const PyScript& s) { return s.script.path; })
      .def_prop_ro("cut_count", [](const PyScript& s) { return s.script.cuts.size(); })
      .def_prop_ro("simulated", [](const PyScript& s) { return s.script.simulation.has_value(); })
      .def_prop_ro("fps", [](const PyScript& s) { return s.script.simulation ? s.script.simulation->fps : 24.0; });
  m.def("_read_script", [](const std::string& path) {
    auto out = std::make_unique<PyScript>();
    nb::gil_scoped_release release;
    out->script = tear::read_cut_script(path);
    return out.release();
  }, nb::rv_policy::take_ownership);
  m.def("_parse_script", [](const std::string& text, const std::string& name) {
    auto out = std::make_unique<PyScript>();
    nb::gil_scoped_release release;
    out->script = tear::parse_cut_script(text, name);
    return out.release();
  }, nb::rv_policy::take_ownership);

  nb::class_<FrameIterator>(m, "FrameIterator")
      .def("__iter__", [](nb::handle self) { return self; })
      .def("__next__", &next_frame)
      .def("__len__", [](const FrameIterator& it) { return it.frame_count - it.next_frame + 1; })
      .def_ro("frame_count", &FrameIterator::frame_count)
      .def_ro("start_frame", &FrameIterator::start_frame);

  m.def("_run_frames", [](const PyMesh& mesh, const PyScript& script, const std::string& device_spec, int start_frame,
                          int frames) {
    const tear::Device device = pick_device(device_spec);
    auto it = std::make_unique<FrameIterator>();
    it->input = std::make_shared<const PyMesh>(mesh);
    it->script = script.script;
    it->device = device;
    it->start_frame = start_frame;
    {
      nb::gil_scoped_release release;
      // Every check of `tear run` but those of outputs (there are none): frames, frame numbers,
      // the script against the mesh, the mesh cuttable, the pins.
      tear::RunOptions options;
      options.output_pattern = "frame.#.ply";
      options.frames = frames;
      options.start_frame = start_frame;
      options.device = device;
      const tear::RunPlan plan = tear::check_run_plan(it->input->mesh, it->input->source, it->script, options);
      it->frame_count = plan.frame_count;
      it->cloth = std::make_unique<tear::Cloth>(it->input->mesh, device);
    }
    return it.release();
  }, nb::rv_policy::take_ownership);

  m.def("_run_to_files", [](const PyMesh& mesh, const PyScript& script, const std::string& device_spec,
                            const std::string& output, int start_frame, int frames, const std::string& report,
                            std::optional<std::string> up_axis, std::optional<double> meters_per_unit,
                            const std::string& checkpoint, int checkpoint_every, bool resume, int writer_threads) {
    // The order of `tear run`'s checks (tool/run_command.cpp).
    const tear::Device device = pick_device(device_spec);
    tear::FramePattern(output).check(1);
    if ((up_axis || meters_per_unit) && !tear::is_usd_path(output))
      throw tear::Error(tear::ErrorKind::usage,
                        "--up-axis and --meters-per-unit apply to USD output only (.usda, .usd), not to '" + output +
                            "'");
    tear::RunOptions run;
    run.up_axis = tear::parse_up_axis(up_axis.value_or("Y"));
    if (meters_per_unit && !(*meters_per_unit > 0 && *meters_per_unit < HUGE_VAL))
      throw tear::Error(tear::ErrorKind::usage, "meters_per_unit: expected a finite number > 0");
    run.output_pattern = output;
    run.frames = frames;
    run.device = device;
    run.report_path = report;
    run.start_frame = start_frame;
    run.meters_per_unit = meters_per_unit.value_or(1.0);
    run.result_options = result_options(mesh.read);
    run.checkpoint_path = checkpoint;
    run.checkpoint_every = checkpoint_every;
    run.resume = resume;
    run.writer_threads = writer_threads;
    run.check_outputs = true;
    run.input_files = {{"mesh", mesh.source}, {"script", script.script.path}};
    tear::RunSummary summary;
    {
      nb::gil_scoped_release release;
      const tear::RunPlan plan = tear::check_run_plan(mesh.mesh, mesh.source, script.script, run);
      run.plan_checked = true;
      tear::remove_stale_temporaries(plan.outputs);
      StopHandlers handlers;
      run.stop = &stop_requested;
      summary = tear::run_to_files(mesh.mesh, mesh.source, script.script, run);
    }
    nb::dict out;
    out["frames"] = summary.frames;
    out["faces"] = summary.faces;
    out["wall_ms"] = summary.wall_ms;
    return out;
  }, "mesh"_a, "script"_a, "device"_a, "output"_a, "start_frame"_a, "frames"_a, "report"_a, "up_axis"_a.none(),
     "meters_per_unit"_a.none(), "checkpoint"_a, "checkpoint_every"_a, "resume"_a, "writer_threads"_a);

  nb::class_<PyCloth>(m, "Cloth")
      .def_prop_ro("node_count", [](const PyCloth& c) { return c.cloth->node_count(); })
      .def_prop_ro("face_count", [](const PyCloth& c) { return c.cloth->face_count(); })
      .def_prop_ro("device", [](const PyCloth& c) { return std::string(tear::to_string(c.cloth->device())); })
      .def_prop_ro("simulated", [](const PyCloth& c) { return c.cloth->simulated(); })
      .def("_cut", [](PyCloth& c, const std::vector<std::array<double, 2>>& polyline, const std::string& space,
                      double snap) {
        tear::Cut cut;
        cut.kind = tear::CutKind::polyline;
        cut.space = parse_space(space);
        if (polyline.size() < 2)
          throw tear::Error(tear::ErrorKind::usage, "polyline: expected at least 2 points, got " +
                                                        std::to_string(polyline.size()));
        for (const auto& p : polyline)
          if (!std::isfinite(p[0]) || !std::isfinite(p[1]))
            throw tear::Error(tear::ErrorKind::usage, "polyline: a point is not finite");
        if (!(snap >= 0 && snap < 0.5))
          throw tear::Error(tear::ErrorKind::usage, "snap: expected a number in [0, 0.5)");
        if (cut.space == tear::CutSpace::uv && !c.has_uv)
          throw tear::input_error(c.source, "a \"uv\" cut needs UVs, and the mesh has none");
        cut.polyline2 = polyline;
        tear::CutStats stats;
        {
          nb::gil_scoped_release release;
          stats = c.cloth->cut({tear::to_cut_line(cut)}, tear::CutOptions{snap});
        }
        nb::dict out;
        out["nodes_before"] = stats.nodes_before;
        out["nodes_after"] = stats.nodes_after;
        out["faces_before"] = stats.faces_before;
        out["faces_after"] = stats.faces_after;
        out["ms"] = stats.total_ms;
        return out;
      })
      .def("_step", [](PyCloth& c, int frames) {
        if (frames < 0) throw tear::Error(tear::ErrorKind::usage, "frames: expected an integer >= 0");
        nb::gil_scoped_release release;
        for (int i = 0; i < frames; ++i) {
          c.cloth->step();
          ++c.frames_stepped;
          if (!c.cloth->state_is_finite())
            throw tear::runtime_error(c.source + ": frame " + std::to_string(c.frames_stepped) +
                                      ": the simulation diverged (a position or velocity is not finite); lower the "
                                      "stiffness or raise the substeps or iterations");
        }
      })
      .def("_positions", &cloth_positions)
      .def("_positions_device", &dlpack_device)
      .def("_set_positions", &set_cloth_positions, "points"_a.noconvert())
      .def("_mesh", [](const PyCloth& c) {
        auto out = std::make_unique<PyMesh>();
        {
          nb::gil_scoped_release release;
          const bool normals = c.cloth->simulated() && c.cloth->has_corner_normals();
          out->mesh = c.cloth->mesh_later(!normals).take();
          if (normals) out->mesh.corner_normal = tear::area_weighted_corner_normals(out->mesh);
        }
        out->source = c.source;
        out->fps = c.simulation ? c.simulation->fps : 24.0;
        out->fill_ids();
        return out.release();
      }, nb::rv_policy::take_ownership);

  m.def("_make_cloth", [](const PyMesh& mesh, const std::string& device_spec, const PyScript* script) {
    const tear::Device device = pick_device(device_spec);
    auto out = std::make_unique<PyCloth>();
    out->has_uv = mesh.mesh.has_uv();
    out->source = mesh.source;
    {
      nb::gil_scoped_release release;
      if (script) {
        tear::check_run_inputs(script->script, mesh.mesh, mesh.source, device);
      } else {
        tear::check_cuttable(mesh.mesh, mesh.source, device);
      }
      out->cloth = std::make_unique<tear::Cloth>(mesh.mesh, device);
      if (script && script->script.simulation) {
        out->simulation = script->script.simulation;
        out->cloth->simulate(*script->script.simulation);
      }
    }
    return out.release();
  }, "mesh"_a, "device"_a, "script"_a.none(), nb::rv_policy::take_ownership);
}
