// tear: the step job of the cloth engine: the solver over the cloth's model, frame by frame or
// substep by substep, with the tearing check after every substep (docs/simulation.md, *Tearing*).
// Only for device code (the .inl files).
#pragma once

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <future>
#include <limits>
#include <memory>
#include <optional>
#include <system_error>
#include <type_traits>
#include <utility>
#include <vector>

#include <thrust/copy.h>
#include <thrust/fill.h>
#include <thrust/for_each.h>
#include <thrust/functional.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/iterator/transform_iterator.h>
#include <thrust/reduce.h>

#include "backend/backend.h"
#include "backend/host_worker.h"
#include "cloth/cloth_cutting.h"
#include "cloth/collision_job.h"
#include "cloth/crack_growth.h"
#include "cloth_data/device_cloth.h"
#include "node_identity.h"
#include "sim/pd_solver_device.h"
#include "strain_rate.h"
#include "tear/cloth.h"
#include "tear/device.h"
#include "tear/error.h"
#include "tear/simulation_options.h"
#include "tear_cracks.h"

namespace tear::backend {

template <class System>
class StepJob {
 public:
  /// Starts stepping with `options`; the solver's model is made at the first step.
  void start(DeviceCloth<System>& cloth, const SimulationOptions& options) {
    options_ = options;
    solver_.reset();
    field_.reset();
    collides_ = options_.collides();
    if (collides_) collision_.start(cloth, options_);
    if (options_.tearing.enabled()) {
      // The fabric's strength per face, carried by cuts from here on.
      const std::vector<float> strength =
          face_strength_field(to_host<float>(cloth.node_rest), to_host<index_t>(cloth.face_nodes),
                              to_host<float>(cloth.corner_uv), options_.tearing, options_.source);
      assign_from_host(cloth.face_strength, strength);
      min_strength_ = strength.empty() ? 1.0 : *std::min_element(strength.begin(), strength.end());
      start_faces_ = cloth.face_count();
      face_budget_ = options_.tearing.face_budget(start_faces_);
    }
  }
  /// The mesh changed (a cut, a tear, a loaded checkpoint): the model and crack field are rebuilt.
  void mesh_changed() {
    stale_ = true;
    if (field_) spare_ = std::move(field_);  // its memory, for the next view's
    field_.reset();
    view_build_ = {};  // a view still being built is of the mesh before: its result is dropped
  }

  /// Steps frame `frame` of `cloth`, tearing it through `cutter` between substeps. With `stop`,
  /// looks at it before every substep: false when it was set before the last one (the frame part
  /// done, Cloth::step_frame).
  bool step(DeviceCloth<System>& cloth, CutJob<System>& cutter, int frame, TearStats& torn,
            const volatile std::sig_atomic_t* stop) {
    torn = TearStats{};
    if (!options_.tearing.enabled() && !collides_) {
      refresh_solver(cloth);
      if (stop != nullptr) return step_watching(cloth, frame, *stop);
      solver_->step_in_place(raw<float>(cloth.node_pos), raw<float>(cloth.node_vel), frame);
      return true;
    }
    // Torn between substeps: the next substep steps the torn cloth with its new model. Marks in
    // the backend's queue time the parts, read once the step's work is done.
    const int substeps = options_.substeps;
    if (mark_count_ < substeps) {
      marks_ = std::make_unique<StepMarks[]>(static_cast<std::size_t>(substeps));
      mark_count_ = substeps;
    }
    int done = 0;  // substeps stepped: all of them unless stopped
    for (; done < substeps; ++done) {
      // Each substep waits for the backend (the tearing check reads a stretch back), so the stop
      // is looked at as the substeps end.
      if (stop != nullptr && *stop) break;
      const int s = done;
      StepMarks& m = marks_[s];
      m.rebuilt = !solver_ || stale_;
      if (m.rebuilt) m.rebuild_start.record();
      refresh_solver(cloth);
      if (m.rebuilt) m.rebuild_end.record();
      m.substep_start.record();
      keep_start(cloth);
      m.start_kept.record();
      if (collides_) collision_.begin(cloth);
      solver_->step_substep_in_place(raw<float>(cloth.node_pos), raw<float>(cloth.node_vel), frame, s);
      m.substep_end.record();
      limit_strain_rate(cloth);
      m.limit_end.record();
      if (collides_) collision_.resolve(cloth, frame, s);
      m.collision_end.record();
      const index_t faces_before = cloth.face_count();
      m.applied = options_.tearing.enabled() && tear(cloth, cutter, m, torn);
      if (!options_.tearing.enabled()) m.check_end.record();
      // Only a tear stops the run (the script's own cuts add faces as they were asked to).
      if (cloth.face_count() > faces_before && cloth.face_count() > face_budget_) over_budget(cloth, frame);
    }
    Traits<System>::synchronize();
    if (collides_) {
      torn.collision_bytes = collision_.bytes();
      torn.held_nodes = collision_.held_nodes();
    }
    for (int s = 0; s < done; ++s) {
      const StepMarks& m = marks_[s];
      if (m.rebuilt) torn.rebuild_ms += QueueMark::elapsed_ms(m.rebuild_start, m.rebuild_end);
      torn.solver_ms += QueueMark::elapsed_ms(m.start_kept, m.substep_end);
      torn.collision_ms += QueueMark::elapsed_ms(m.limit_end, m.collision_end);
      // The strain rate limit is tearing's: counted with its check.
      const double limit =
          QueueMark::elapsed_ms(m.substep_start, m.start_kept) + QueueMark::elapsed_ms(m.substep_end, m.limit_end);
      torn.limit_ms += limit;
      torn.check_ms += limit + QueueMark::elapsed_ms(m.collision_end, m.check_end);
      if (m.applied) torn.apply_ms += QueueMark::elapsed_ms(m.check_end, m.apply_end);
    }
    return done == substeps;
  }

 private:
  /// The tearing's strain rate limit (kernels/strain_rate.h): on for a tearing cloth unless its
  /// `strain_rate_limit` is 0, or the collision pass runs (its moves, made without the contacts,
  /// would cross layers the pass keeps apart; the pass keeps faces from passing through each other).
  bool limits_strain_rate() const {
    return options_.tearing.enabled() && options_.tearing.strain_rate_limit > 0 && !collides_;
  }
  /// The substep's start positions, which the limit measures against.
  void keep_start(const DeviceCloth<System>& cloth) {
    if (!limits_strain_rate()) return;
    resize_for_overwrite(start_pos_, cloth.node_pos.size());
    thrust::copy(Traits<System>::policy(), cloth.node_pos.begin(), cloth.node_pos.end(), start_pos_.begin());
  }
  /// After the solver's substep: what it did limited, in `strain_rate_passes` passes (the first
  /// reads the positions, the last writes positions and velocities).
  void limit_strain_rate(DeviceCloth<System>& cloth) {
    if (!limits_strain_rate() || cloth.node_count() == 0) return;
    const double h = options_.step_seconds();
    resize_for_overwrite(rate_[0], cloth.node_pos.size());
    resize_for_overwrite(rate_[1], cloth.node_pos.size());
    resize_for_overwrite(excess_, kernels::strain_rate_passes);
    kernels::limit_strain_rate pass{raw<index_t>(cloth.face_nodes),
                                    raw<index_t>(cloth.topo.node_face_offset),
                                    raw<index_t>(cloth.topo.node_faces),
                                    raw<float>(start_pos_),
                                    raw<std::uint8_t>(cloth.node_pinned),
                                    nullptr,
                                    nullptr,
                                    raw<float>(cloth.node_pos),
                                    raw<float>(cloth.node_vel),
                                    static_cast<float>(h),
                                    static_cast<float>(1 / h),
                                    static_cast<float>(options_.tearing.strain_rate_limit / h),
                                    false,
                                    raw<int>(excess_)};
    thrust::fill(Traits<System>::policy(), excess_.begin(), excess_.end(), 0);
    for (int p = 0; p < kernels::strain_rate_passes; ++p) {
      pass.vel_in = p == 0 ? nullptr : raw<float>(rate_[(p + 1) % 2]);
      pass.vel_out = raw<float>(rate_[p % 2]);
      pass.finish = p + 1 == kernels::strain_rate_passes;
      pass.pass = p;
      // A warp a node on a GPU (the same bits), where the lanes' count fits an index.
      if (!std::is_same<System, Omp>::value && cloth.node_count() <= std::numeric_limits<index_t>::max() / 32)
        for_each_index<System>(32 * cloth.node_count(), kernels::limit_strain_rate_by_warp{pass});
      else
        for_each_index<System>(cloth.node_count(), pass);
    }
  }

  using QueueMark = typename Traits<System>::QueueMark;
  /// A torn substep's parts, marked in the backend's queue: the model's rebuild (where the mesh
  /// changed), the substep, the check, the tear's application (where the cloth tore).
  struct StepMarks {
    QueueMark rebuild_start, rebuild_end, substep_start, start_kept, substep_end, limit_end, collision_end, check_end,
        apply_end;
    bool rebuilt = false, applied = false;
  };

  /// A frame without tearing, substep by substep (the same work as `step_in_place`'s whole frame,
  /// so the same bytes), `stop` looked at before each. On an asynchronous backend (CUDA) the
  /// substeps queued are waited for in chunks, doubled while a chunk takes under 50 ms: a stop
  /// lands within about 0.1 s and a substep, and a frame of short substeps waits a few times only.
  /// On the CPU each substep is done when its call returns.
  bool step_watching(DeviceCloth<System>& cloth, int frame, const volatile std::sig_atomic_t& stop) {
    using Clock = std::chrono::steady_clock;
    int chunk = 1, queued = 0;
    Clock::time_point chunk_start = Clock::now();
    for (int s = 0; s < options_.substeps; ++s) {
      if (stop) return false;
      solver_->step_substep_in_place(raw<float>(cloth.node_pos), raw<float>(cloth.node_vel), frame, s);
      if (++queued < chunk) continue;
      Traits<System>::synchronize();
      const Clock::time_point now = Clock::now();
      if (now - chunk_start < std::chrono::milliseconds(50) && chunk < (1 << 20)) chunk *= 2;
      queued = 0;
      chunk_start = now;
    }
    return true;
  }

  void refresh_solver(const DeviceCloth<System>& cloth) {
    if (solver_ && !stale_) return;
    if (solver_)
      rebuild_pd_solver<System>(*solver_, cloth);  // in the old model's memory, grown where needed
    else
      solver_ = make_pd_solver<System>(cloth, options_);
    stale_ = false;
  }

  /// A tear left the cloth with more faces than `tearing.max_faces` (or its default): the run
  /// stops there, a runtime `Error` naming the key.
  [[noreturn]] void over_budget(const DeviceCloth<System>& cloth, int frame) const {
    const std::int64_t given = options_.tearing.max_faces;
    throw runtime_error(
        options_.source + ": frame " + std::to_string(frame) + ": simulation.tearing.max_faces: tearing left the cloth with " +
        std::to_string(cloth.face_count()) + " faces, over the limit of " + std::to_string(face_budget_) +
        (given > 0 ? std::string()
                   : " (the default: " + std::to_string(simulation_limits::default_tear_face_factor) +
                         " times the " + std::to_string(start_faces_) + " faces the simulation started with, at least " +
                         std::to_string(simulation_limits::default_tear_face_floor) + ")") +
        "; raise tearing.max_faces, or tearing.stretch so that less tears");
  }

  /// The largest stretch no limit can be under: where no face passes it, nothing tears.
  double quiet_limit() const {
    const TearingOptions& t = options_.tearing;
    double k = std::min(1.0, t.seam_strength);
    if (t.has_weave) k = std::min(k, t.weave.weft_strength);
    return std::min(t.stretch, t.start_stretch()) * min_strength_ * k;
  }

  /// Grows the cracks where the stretch around them passes the limits (crack_growth.h). The
  /// faces' largest stretch is reduced on the backend and read back: below `quiet_limit` that is
  /// all. Returns whether the cloth tore.
  bool tear(DeviceCloth<System>& cloth, CutJob<System>& cutter, StepMarks& m, TearStats& torn) {
    const double largest = largest_of(
        cloth.face_count(), kernels::face_stretch_of{raw<index_t>(cloth.face_nodes), raw<float>(cloth.node_rest),
                                                     raw<float>(cloth.node_pos)});
    if (!(largest > quiet_limit())) {
      m.check_end.record();
      return false;
    }
    const auto t0 = std::chrono::steady_clock::now();
    if (!field_) {
      take_view(cloth);
      torn.view_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    } else {
      view_ms_[0] = view_ms_[1] = view_ms_[2] = 0;
    }
    const auto t1 = std::chrono::steady_clock::now();
    // The discs and the faces crack growth would look at, summed on the backend: where nothing
    // there can pass its limit, the substep is quiet without reading the positions back.
    if (!may_cut(cloth)) {
      // TEAR_DEBUG_CRACK_CHECK=1 (the tests): the plan is made anyway, and must cut nothing.
      static const bool check_skips = std::getenv("TEAR_DEBUG_CRACK_CHECK") != nullptr;
      if (check_skips && !field_->plan(to_host<float>(cloth.node_pos)).cuts.empty())
        throw Error(ErrorKind::runtime, "tearing: the backend's check skipped a substep whose plan cuts");
      if (std::getenv("TEAR_DEBUG_CRACK_TIMES"))
        std::fprintf(stderr, "check: field %.3f ms, quiet on the backend (discs %.3f ms, starts %.3f ms; view read %.3f, "
                     "built %.3f, probes %.3f ms)\n",
                     std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count(),
                     check_ms_[0], check_ms_[1], view_ms_[0], view_ms_[1], view_ms_[2]);
      m.check_end.record();
      return false;
    }
    const std::vector<float> node_pos = positions(cloth);
    const auto t2 = std::chrono::steady_clock::now();
    const CrackPlan plan = field_->plan(node_pos);
    const auto t3 = std::chrono::steady_clock::now();
    if (std::getenv("TEAR_DEBUG_CRACK_TIMES"))
      std::fprintf(stderr, "check: field %.3f ms, positions %.3f ms, plan %.3f ms (discs %.3f ms, starts %.3f ms; "
                   "view read %.3f, built %.3f, probes %.3f ms)\n",
                   std::chrono::duration<double, std::milli>(t1 - t0).count(),
                   std::chrono::duration<double, std::milli>(t2 - t1).count(),
                   std::chrono::duration<double, std::milli>(t3 - t2).count(), check_ms_[0], check_ms_[1], view_ms_[0],
                   view_ms_[1], view_ms_[2]);
    m.check_end.record();
    if (plan.cuts.empty()) return false;
    CutOptions cut_options;
    cut_options.snap = options_.tearing.snap;
    CutStats stats;
    StageClock clock(false, stats.stage_ms.data());
    Remesher<System>& remesher = cutter.remesher();
    if (remesher.cut_info_from_paths(cloth, plan.cuts, cut_options, clock) &&
        remesher.apply_cut_info(cloth, cut_options, stats, clock, false)) {
      cutter.reapply_box_pins(cloth);
      mesh_changed();
      start_view(cloth);
      torn.events += plan.events;
      torn.length += plan.length;
    }
    m.apply_end.record();
    return true;
  }

  /// Crack growth's view of a torn mesh and its probes, built on the host.
  struct ViewBuild {
    std::optional<CrackField> field;
    CrackProbes probes;
    double read_ms = 0, build_ms = 0;
  };
  static ViewBuild build_view(CrackMesh mesh, const TearingOptions& options, CrackField* recycled) {
    const auto t0 = std::chrono::steady_clock::now();
    ViewBuild b;
    b.field.emplace(std::move(mesh), options, recycled);
    b.probes = b.field->probes();
    b.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return b;
  }

  /// After a tear on a GPU: the torn mesh read back, and its view built on a thread of the host's
  /// while the backend runs the next substep (the host would wait for it otherwise). The view is
  /// the same whichever thread builds it. On the CPU the substep needs the host's threads: the
  /// check builds the view where it needs it.
  void start_view(const DeviceCloth<System>& cloth) {
    if (std::is_same<System, Omp>::value) return;
    const auto t0 = std::chrono::steady_clock::now();
    CrackMesh mesh;
    std::optional<CrackField> old = read_for_view(cloth, mesh);
    const double read_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    // The worker's OpenMP team: this thread's limit (`--threads`; a new thread starts with
    // OpenMP's) less the one this thread keeps, waiting for the device meanwhile.
    const int threads = std::max(1, cpu_threads() - 1);
    try {
      std::packaged_task<ViewBuild()> task(
          [mesh = std::move(mesh), options = options_.tearing, read_ms, old = std::move(old), threads]() mutable {
            set_cpu_threads(threads);
            ViewBuild b = build_view(std::move(mesh), options, old ? &*old : nullptr);
            b.read_ms = read_ms;
            return b;
          });
      view_build_ = task.get_future();
      view_worker_.run(std::move(task));
    } catch (const std::system_error&) {
      view_build_ = {};  // no thread to be had: the check builds it
    }
  }

  /// Crack growth's view of the mesh as it is: the one started after the tear, or built now.
  void take_view(const DeviceCloth<System>& cloth) {
    const auto t0 = std::chrono::steady_clock::now();
    ViewBuild b;
    if (view_build_.valid()) {
      b = view_build_.get();  // the build's error, if any, is thrown here
    } else {
      CrackMesh mesh;
      std::optional<CrackField> old = read_for_view(cloth, mesh);
      b = build_view(std::move(mesh), options_.tearing, old ? &*old : nullptr);
      b.read_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() - b.build_ms;
    }
    field_ = std::move(b.field);
    const auto t1 = std::chrono::steady_clock::now();
    upload_probes(std::move(b.probes));
    view_ms_[0] = b.read_ms;
    view_ms_[1] = b.build_ms;
    view_ms_[2] = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count();
  }

  /// The cloth read into `mesh` for a new view, in the memory of the view before's mesh; returns
  /// that view (empty: none), whose other arrays the build takes.
  std::optional<CrackField> read_for_view(const DeviceCloth<System>& cloth, CrackMesh& mesh) {
    std::optional<CrackField> old = std::exchange(spare_, std::nullopt);
    if (old) mesh = old->release_mesh();
    crack_mesh(cloth, mesh);
    return old;
  }

  /// The crack field's probes (CrackProbes) into the backend's memory, with its host half.
  void upload_probes(CrackProbes probes) {
    std::vector<index_t> keys(probes.faces.size());
    for (std::size_t p = 0; p < probes.count(); ++p)
      std::fill(keys.begin() + probes.offsets[p], keys.begin() + probes.offsets[p + 1], static_cast<index_t>(p));
    assign_from_host(probe_keys_, keys);
    assign_from_host(probe_faces_, probes.faces);
    assign_from_host(may_start_, probes.may_start);
    assign_from_host(cell_key_, probes.cell_key);
    assign_from_host(cell_face_, probes.cell_face);
    resize_for_overwrite(sum_keys_, probes.count());
    resize_for_overwrite(sums_, probes.count());
    centroids_ready_ = false;  // a new view: the faces may have changed
    probes_ = std::move(probes);
  }

  /// Whether crack growth may cut this substep (CrackField::may_cut), from the discs' sums and the
  /// largest smoothed stretch of a face that may start a crack, computed on the backend and read back.
  bool may_cut(const DeviceCloth<System>& cloth) {
    const float* strength = cloth.face_strength.empty() ? nullptr : raw<float>(cloth.face_strength);
    const thrust::counting_iterator<index_t> zero(0);
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<double> sums(8 * probes_.count(), 0.0);
    if (!probe_faces_.empty()) {
      // Summed per disc by key (no atomics). The sums only gate the host's plan, with a margin, so
      // their last bits do not reach a result.
      const auto terms = thrust::make_transform_iterator(
          zero, kernels::disc_term{raw<index_t>(probe_faces_), raw<index_t>(cloth.face_nodes),
                                   raw<float>(cloth.node_rest), raw<float>(cloth.node_pos), strength});
      thrust::reduce_by_key(Traits<System>::policy(), probe_keys_.begin(), probe_keys_.end(), terms, sum_keys_.begin(),
                            sums_.begin(), thrust::equal_to<index_t>(), kernels::add_disc_sums());
      // The keys come out as the discs with faces, in order: the i-th sum is the i-th such disc's,
      // so only the sums are read back.
      const std::vector<kernels::DiscSums> values = to_host<kernels::DiscSums>(sums_);
      std::size_t i = 0;
      for (std::size_t p = 0; p < probes_.count(); ++p)
        if (probes_.offsets[p + 1] > probes_.offsets[p]) {
          std::copy(values[i].v, values[i].v + 8, &sums[8 * p]);
          ++i;
        }
    }
    const auto t1 = std::chrono::steady_clock::now();
    // The start faces' discs on a GPU, where they cost a few microseconds; on the CPU each face over
    // the limit would sum its disc on one of a few threads, and the faces' own stretch bounds the
    // start instead (a plan more often, the same decisions).
    const kernels::start_stretch_ratio_of own{raw<index_t>(cloth.face_nodes), raw<float>(cloth.node_rest),
                                              raw<float>(cloth.node_pos), strength, raw<std::uint8_t>(may_start_),
                                              options_.tearing.start_stretch()};
    double start = 0;
    if (std::is_same<System, Omp>::value) {
      start = largest_of(cloth.face_count(), own);
    } else {
      const kernels::FaceGrid grid{raw<std::int64_t>(cell_key_), raw<index_t>(cell_face_),
                                   static_cast<index_t>(cell_key_.size()), probes_.cell};
      // Each face's rest centroid once per view, its disc term once per check: a candidate's disc
      // reads them (the same values, summed in the same order, as computing them there).
      const index_t faces = cloth.face_count();
      if (!centroids_ready_) {
        resize_for_overwrite(face_centroids_, 3 * std::size_t(faces));
        for_each_index<System>(
            faces, kernels::store_rest_centroids{raw<index_t>(cloth.face_nodes), raw<float>(cloth.node_rest),
                                                 raw<double>(face_centroids_)});
        centroids_ready_ = true;
      }
      resize_for_overwrite(face_terms_, faces);
      for_each_index<System>(
          faces, kernels::store_disc_terms{raw<index_t>(cloth.face_nodes), raw<float>(cloth.node_rest),
                                           raw<float>(cloth.node_pos), strength, raw<kernels::DiscSums>(face_terms_)});
      const kernels::start_ratio_of ratio{own, grid, probes_.radius, raw<kernels::DiscSums>(face_terms_),
                                          raw<double>(face_centroids_)};
      if (faces <= std::numeric_limits<index_t>::max() / 32) {
        // A warp a face (kernels::start_ratio_by_warp): its disc's entries shared by 32 lanes.
        resize_for_overwrite(values_, faces);
        for_each_index<System>(32 * faces, kernels::start_ratio_by_warp{ratio, raw<double>(values_)});
        start = largest_stored();
      } else {
        start = largest_of(faces, ratio);
      }
    }
    const auto t2 = std::chrono::steady_clock::now();
    check_ms_[0] = std::chrono::duration<double, std::milli>(t1 - t0).count();
    check_ms_[1] = std::chrono::duration<double, std::milli>(t2 - t1).count();
    return field_->may_cut(probes_, sums, start);
  }

  /// The largest of `f(i)` over [0, count) and 0: each value by one thread into a buffer
  /// (`for_each_index`), then the buffer reduced. A reduction or transform that calls a costly `f`
  /// itself hands each thread a run of elements in turn (CUB's even share: a few blocks for a mesh
  /// of 38K faces, a smoothed disc per element); one thread an element spreads `f` over the whole
  /// device. The maximum is the same whichever way.
  template <class F>
  double largest_of(index_t count, const F& f) {
    resize_for_overwrite(values_, count);
    for_each_index<System>(count, kernels::store_value<F>{f, raw<double>(values_)});
    return largest_stored();
  }
  /// The largest of `values_` and 0.
  double largest_stored() {
    return thrust::reduce(Traits<System>::policy(), values_.begin(), values_.end(), 0.0, thrust::maximum<double>());
  }

  /// Where a backend array's copy lies in `read_`'s batch.
  struct Part {
    std::size_t offset, count;
  };
  /// Queues the copy of backend vector `v` into `read_`'s batch.
  template <class V>
  Part queue_read(const V& v) {
    using T = typename V::value_type;
    return Part{read_.template queue<T>(raw<T>(v), v.size()), v.size()};
  }
  /// After `read_.wait()`: the copy queued as `part` into host vector `out`.
  template <class T>
  void take_read(const Part& part, std::vector<T>& out) const {
    const T* from = read_.template at<T>(part.offset);
    out.assign(from, from + part.count);
  }

  /// What crack growth reads of the cloth, on the host: its arrays queued into one read-back
  /// through page-locked memory and waited for once (a copy each into pageable memory waited for
  /// every one). Of the topology only what crack growth looks up; the UVs only where a weave or
  /// seams need them; which corners' edges are torn marked on the backend, where the origins they
  /// are told from already are. Into `mesh`, whose arrays keep their memory where it suffices.
  void crack_mesh(const DeviceCloth<System>& c, CrackMesh& mesh) {
    const index_t faces = c.topo.face_count;
    resize_for_overwrite(corner_torn_, 3 * std::size_t(faces));
    for_each_index<System>(
        3 * faces, kernels::mark_torn_corners{raw<index_t>(c.topo.face_edges), raw<index_t>(c.topo.edge_faces),
                                              raw<index_t>(c.face_origin), raw<float>(c.corner_origin),
                                              raw<std::uint8_t>(c.input_face_border), raw<std::uint8_t>(corner_torn_)});
    read_.clear();
    const TearingOptions& o = options_.tearing;
    const bool uv_needed = o.has_weave || o.seam_strength != 1;
    const Part rest = queue_read(c.node_rest), face_nodes = queue_read(c.face_nodes),
               uv = uv_needed ? queue_read(c.corner_uv) : Part{0, 0}, strength = queue_read(c.face_strength),
               edge_nodes = queue_read(c.topo.edge_nodes), edge_faces = queue_read(c.topo.edge_faces),
               face_edges = queue_read(c.topo.face_edges), node_face_offset = queue_read(c.topo.node_face_offset),
               node_faces = queue_read(c.topo.node_faces), torn = queue_read(corner_torn_),
               held = queue_read(c.node_pinned);
    read_.wait();
    take_read(rest, mesh.node_rest);
    take_read(face_nodes, mesh.face_nodes);
    take_read(uv, mesh.corner_uv);
    take_read(strength, mesh.face_strength);
    take_read(torn, mesh.corner_torn);
    take_read(held, mesh.node_held);
    Topology& t = mesh.topo;
    t.node_count = c.topo.node_count;
    t.face_count = faces;
    t.edge_count = c.topo.edge_count;
    take_read(edge_nodes, t.edge_nodes);
    take_read(edge_faces, t.edge_faces);
    take_read(face_edges, t.face_edges);
    take_read(node_face_offset, t.node_face_offset);
    take_read(node_faces, t.node_faces);
  }

  /// The cloth's positions on the host, through the same page-locked read-back.
  std::vector<float> positions(const DeviceCloth<System>& c) {
    read_.clear();
    const Part part = queue_read(c.node_pos);
    read_.wait();
    std::vector<float> out;
    take_read(part, out);
    return out;
  }

  SimulationOptions options_;
  bool collides_ = false;            // substeps end in the collision pass
  CollisionJob<System> collision_;
  std::unique_ptr<PdSolver::Impl> solver_;                       // the model of the mesh it was built for
  bool stale_ = false;                                           // the mesh changed since
  std::optional<CrackField> field_;                              // crack growth's view of the rest mesh, while it holds
  std::optional<CrackField> spare_;                              // the view before, its memory for the next
  ReadBack<System> read_;                                        // crack growth's reads of the cloth
  vector<System, std::uint8_t> corner_torn_;                     // CrackMesh::corner_torn, marked on the backend
  CrackProbes probes_;                                           // the field's probes, and in the backend's memory:
  vector<System, index_t> probe_keys_, probe_faces_, sum_keys_;  // disc of each entry, its face
  vector<System, std::uint8_t> may_start_;
  vector<System, std::int64_t> cell_key_;
  vector<System, index_t> cell_face_;
  vector<System, kernels::DiscSums> sums_;
  vector<System, float> start_pos_, rate_[2];  // the strain rate limit's start positions and mean velocities
  vector<System, int> excess_;                 // [strain_rate_passes] the limit's pass p found an altitude to limit
  vector<System, kernels::DiscSums> face_terms_;  // every face's disc term, this check's (GPU)
  vector<System, double> values_;                 // largest_of's per-element values
  vector<System, double> face_centroids_;         // every face's rest centroid, this view's (GPU)
  bool centroids_ready_ = false;
  // For TEAR_DEBUG_CRACK_TIMES: the last may_cut's parts (discs, starts) and the last check's view
  // (read back, built, probes made and uploaded; zeros where it was not rebuilt).
  double check_ms_[2] = {0, 0};
  double view_ms_[3] = {0, 0, 0};
  double min_strength_ = 1;
  std::int64_t start_faces_ = 0;  // the cloth's faces when the simulation started
  std::int64_t face_budget_ = 0;  // the most faces tearing may leave it with
  std::unique_ptr<StepMarks[]> marks_;  // [mark_count_], one per substep
  int mark_count_ = 0;
  std::future<ViewBuild> view_build_;  // the view after the last tear, being built (GPU)
  HostWorker<ViewBuild> view_worker_;  // builds it; last, so first destroyed (waits for its task)
};

}  // namespace tear::backend
