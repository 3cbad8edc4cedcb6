// tear: where the cloth's cracks grow in one substep (docs/simulation.md, *Tearing*), as cut
// paths for the remesher's first half.
//
// A crack is a slit in the rest shape; its tips are the border nodes the cloth surrounds all but
// fully (rest angle sum over 1.5π: the end of a slit; between torn edges, only where the slit's two
// flanks meet). After a substep each tip looks at the stretch smoothed over a disc of `radius`
// around it in the rest shape, not at the one face there: when that passes the limit (times the
// fabric's strength there, along the thread or seam it runs on) the tip advances by `step` across
// the smoothed principal direction, or joins the border or crack it comes within `radius` of,
// unless that would cut off a piece under `min_piece`. Where no tip is near, the most stretched
// place over `start` starts one crack, from the border when it is within `radius`. Each advance is
// a straight rest-space cut, so the path does not follow the triangles, and the same scene tears
// the same way at any resolution. No cut runs into cloth a pin holds whole (a clamp's fabric cannot
// stretch): a tip that would turns along it, as a clamped cloth tears along the clamp's edge.
//
// Example: a 1 m sheet with a slit from (0.5, 0) to (0.5, 0.25) pulled apart along x: the slit's
// end is the one tip; the smoothed stretch there is across x, so the tip advances along +y by
// `step` (one cut from (0.5, 0.25) to (0.5, 0.25 + step)), substep after substep, until it comes
// within `radius` of the top border and joins it: two pieces.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "tear/cloth.h"
#include "tear/mesh.h"
#include "tear/simulation_options.h"
#include "tear/topology.h"

namespace tear {

/// The cloth as crack growth reads it, on the host: the rest mesh and what is derived from it
/// (kept while the mesh does not change) and the current positions.
struct CrackMesh {
  std::vector<float> node_rest;      ///< [node_count * 3]
  std::vector<index_t> face_nodes;   ///< [face_count * 3]
  std::vector<float> corner_uv;      ///< [face_count * 6] or empty
  std::vector<float> face_strength;  ///< [face_count] or empty (1)
  /// [face_count * 3] the edge from corner c is a cut or tear; empty: every border edge counts as one
  std::vector<std::uint8_t> corner_torn;
  /// [node_count] nonzero where a pin holds the node; empty: none is held
  std::vector<std::uint8_t> node_held;
  Topology topo;
};

/// What one substep's growth cuts: the paths, and what the report counts.
struct CrackPlan {
  std::vector<CutLine> cuts;
  int events = 0;     ///< tips advanced or joined, and cracks started
  double length = 0;  ///< rest length of the paths, metres
};

/// Where `CrackField::plan` looks, for a check on the backend that lets a substep where nothing can
/// tear skip it: the discs it smooths the stretch over (ahead of each tip, and at each seam that may
/// open from the border) and the faces where a new crack may start. Rest-space data, fixed while
/// the mesh is.
struct CrackProbes {
  std::vector<index_t> offsets{0};      ///< [probes + 1] into `faces`
  std::vector<index_t> faces;           ///< each disc's faces, in the order `smoothed` sums them
  std::vector<double> normal;           ///< [probes * 3] the plane the disc's stretch is measured in
  std::vector<double> limit;            ///< [probes] the least limit held against it, before the strength
  std::vector<double> gain;             ///< [probes] the most a direction's choice scales the opening stretch by
  std::vector<std::uint8_t> may_start;  ///< [faces] a new crack may start there (away from cracks and tips)
  /// The grid of faces by rest centroid the start candidates' discs are gathered from (kernels::FaceGrid).
  std::vector<std::int64_t> cell_key;
  std::vector<index_t> cell_face;
  double cell = 1, radius = 1;  ///< the grid's cell and the smoothing disc's radius, metres
  std::size_t count() const { return limit.size(); }
};

/// Everything of the rest mesh crack growth looks up, built once per mesh.
class CrackField {
 public:
  CrackField(CrackMesh mesh, const TearingOptions& options);
  /// The same, built in the memory of `recycled`, a view of the mesh before (null: none), which is
  /// left empty: a view rebuilt after every tear touches no new pages where it fits in the old one.
  CrackField(CrackMesh mesh, const TearingOptions& options, CrackField* recycled);
  /// The mesh this view was built from, its arrays to be filled again; the view is left unusable.
  CrackMesh release_mesh() { return std::move(m_); }

  /// The cuts of this substep for positions `node_pos` [node_count * 3].
  CrackPlan plan(const std::vector<float>& node_pos) const;

  /// The faces `smoothed` averages over around `p`: the disc of `radius`, doubled up to three times
  /// where it holds no face's centroid.
  std::vector<index_t> disc(const std::array<double, 3>& p) const;
  /// The faces' stretch tensors in rest coordinates (6 values each) at one set of positions, each
  /// computed where first read: a tip's advance reads one disc's faces, and only a crack's start
  /// reads them all.
  class FaceTensors {
   public:
    FaceTensors(const CrackMesh& mesh, const std::vector<float>& node_pos);
    /// Face f's 6 values.
    const double* operator()(index_t f) const {
      if (!ready_[f]) compute(f);
      return &values_[6 * std::size_t(f)];
    }
    /// Every face's, on the host's threads.
    void compute_all() const;

   private:
    void compute(index_t f) const;
    const CrackMesh& m_;
    const std::vector<float>& pos_;
    std::unique_ptr<double[]> values_;  // written where `ready_`: a face's page is touched when read
    mutable std::vector<std::uint8_t> ready_;
  };
  /// The faces' stretch tensors at `node_pos` (kept by reference), for `smoothed`.
  FaceTensors face_tensors(const std::vector<float>& node_pos) const { return FaceTensors(m_, node_pos); }
  /// The rest stretch tensor smoothed over the disc of `radius` around `p` (area weighted, 3×3
  /// symmetric as xx yy zz xy xz yz), and the mean strength there. Public for the tests.
  void smoothed(const std::array<double, 3>& p, const FaceTensors& tensors, double* tensor, double* strength) const;
  /// The largest opening stretch over its limit of any tip (1: at its limit), for the tests.
  double largest_tip_ratio(const std::vector<float>& node_pos) const;
  /// The discs and faces `plan` looks at (CrackProbes).
  CrackProbes probes() const;
  /// Whether `plan` may cut anything: a probe's opening stretch over its limit may pass 1 (`sums`
  /// [probes * 8]: per disc the area-weighted tensor, strength and area, kernels::disc_term), or a
  /// new crack may start (`start_ratio`: the largest smoothed stretch over the start limit of a
  /// face that may start one, kernels::start_ratio_of). Conservative: where it says no, `plan` cuts
  /// nothing.
  bool may_cut(const CrackProbes& probes, const std::vector<double>& sums, double start_ratio) const;
  /// The crack tips: border nodes whose rest angle sum passes 1.5π, and that end a slit where
  /// both their border edges are torn (`ends_slit`).
  const std::vector<index_t>& tips() const { return tips_; }
  /// Each node's piece (faces joined through nodes): the piece's lowest node. For the tests.
  const std::vector<index_t>& node_pieces() const { return node_piece_; }

 private:
  struct Tip;
  using Vec3 = std::array<double, 3>;
  Vec3 rest(index_t n) const;
  /// Tip `n` with its normal, the crack's course (the line fitted through its slit) and its forward
  /// direction; false when the slit gives no direction.
  bool make_tip(index_t n, Tip& tip) const;
  void build();
  /// Takes `old`'s arrays, emptied, for this view's (their memory kept).
  void reuse(CrackField& old);
  void build_grid();
  void build_pieces();
  void build_border();
  /// Whether border node n, with a rest angle sum over 1.5π, ends a slit (a crack tip).
  bool ends_slit(index_t n) const;
  /// Whether border nodes a and b lie on one border (one loop of border edges).
  bool on_one_border(index_t a, index_t b) const;
  template <class F>
  void faces_near(const Vec3& p, double r, F&& f) const;
  /// The path of `tip`'s advance this substep, if it advances; `ratio` its opening stretch over its
  /// limit (0 when it is held back by `min_piece`).
  bool advance(const Tip& tip, const FaceTensors& tensors, std::vector<Vec3>& path, bool& joined, double& ratio) const;
  /// The direction a tip runs in (across the smoothed stretch, along a thread or a seam) and its
  /// opening stretch over its limit; `seam_path` the seam edge it runs along, if it does.
  double choose_direction(const Tip& tip, const double* S, double limit, Vec3& d, std::vector<Vec3>& seam_path) const;
  /// Whether `p` lies within a radius of a crack, or four of a tip.
  bool near_crack(const Vec3& p) const;
  /// `may_start_`: the faces whose centroid is not near a crack (near_crack).
  void mark_may_start();
  /// The faces that may start a crack: over `start`, not in a loaded piece, one per grid cell.
  std::vector<index_t> start_candidates(const std::vector<double>& stretch, const std::vector<index_t>& loaded) const;
  /// A seam reaching the border that opens there, if it passes `best`.
  bool seam_start(const FaceTensors& tensors, const std::vector<index_t>& loaded, double& best,
                  std::vector<Vec3>& path) const;
  /// The path of a new crack, if one starts: not in the pieces `loaded` (sorted) whose tips bear load.
  bool start(const FaceTensors& tensors, const std::vector<double>& stretch, const std::vector<index_t>& loaded,
             std::vector<Vec3>& path) const;
  /// The path of a crack started at face `face` across the stretch (`across`); false when there is
  /// none, with `held` set where cloth a pin holds was in every way it could take.
  bool start_path(index_t face, const Vec3& across, std::vector<Vec3>& path, bool& held) const;
  /// The nearest point of a border edge not within `exclude_walk` of node `from` along the border,
  /// ahead of `p` along `d` (or anywhere with `d` null), within `reach`; false when none.
  bool nearest_border(const Vec3& p, const Vec3* d, double reach, index_t from, Vec3& point, index_t& edge) const;
  /// Whether the straight cut from tip node `tip` (at `at`, in the plane of normal `normal`) to `q`
  /// crosses a border edge that does not end at the tip: a cut across a crack closes a loop, and
  /// what lies between the two is cut off.
  bool crosses_border(index_t tip, const Vec3& at, const Vec3& normal, const Vec3& q) const;
  /// Turns `tip`'s advance (direction `d`, end `q`, `step` long) off cloth a pin holds, where the
  /// smoothed stretch `S` across the new direction still passes `limit`; returns its ratio over the
  /// limit, 0 (d and q as they were) where no turn does.
  double turn_from_held(const Tip& tip, const double* S, double limit, double step, Vec3& d, Vec3& q) const;
  /// Whether a pin holds face f's three nodes.
  bool face_held(index_t f) const {
    const index_t* v = &m_.face_nodes[3 * std::size_t(f)];
    return !m_.node_held.empty() && m_.node_held[v[0]] && m_.node_held[v[1]] && m_.node_held[v[2]];
  }
  /// Whether the straight cut from `a` to `b` (in the plane of normal `normal`) runs into a face
  /// whose three nodes a pin holds: that cloth cannot stretch, and a crack does not cross it.
  bool crosses_held(const Vec3& a, const Vec3& b, const Vec3& normal) const;
  /// The smaller rest area of the two sides a cut from border node `tip` to border edge `edge`
  /// would leave, or a huge value when they are on different loops (nothing is cut off).
  double piece_cut_off(index_t tip, const Vec3& point, index_t edge) const;
  Vec3 thread_direction(index_t face, double du, double dv) const;

  CrackMesh m_;
  TearingOptions options_;
  std::vector<Vec3> face_centroid_, face_normal_;
  std::vector<double> face_area_;
  std::vector<index_t> border_next_, border_prev_;  // [node_count] along the border, or -1
  std::vector<std::uint8_t> border_torn_;           // [node_count] the border edge to border_next_ is a cut or tear
  std::vector<index_t> border_edges_;
  std::vector<std::uint8_t> edge_seam_;
  std::vector<index_t> tips_;
  std::vector<std::uint8_t> may_start_;  // [face_count] !near_crack(centroid), and not held
  bool any_held_ = false;                // a pin holds some face whole (face_held)
  double longest_edge_ = 0;              // the longest rest edge, metres
  std::vector<index_t> node_piece_;      // [node_count] the piece's lowest node
  // Faces by grid cell of side `radius` over their rest centroids: sorted cell keys and faces.
  std::vector<std::int64_t> cell_key_;
  std::vector<index_t> cell_face_;
  double cell_ = 1;
  double radius_ = 1;  // the smoothing radius: `radius`, or two mean edges on a coarser mesh
  double total_area_ = 0;
  /// The build's working arrays, kept for the view built in this one's memory (`reuse`).
  struct Scratch {
    std::vector<double> length, node_angle;  // [edges] rest lengths; [nodes] rest angle sums
    std::vector<std::int64_t> at;            // [faces * 3] each face's cell
    std::vector<index_t> first;              // the grid's counting sort
    std::vector<std::uint8_t> on_border;     // [faces * 3] the corner's opposite edge is on the border
  } scratch_;
};

/// The factor on the limits per face: from `variation` and `seed`, a value noise of feature size
/// `radius` over the rest centroids, 1 + variation × noise in [-1, 1]; times the `strength_map`'s
/// value at the face's UV centroid; all 1 without either. Throws an input `Error` naming `script`
/// and the key where the map needs UVs the mesh lacks (`corner_uv` empty) or makes a face's limit
/// 1 or less (the cloth would tear at rest).
std::vector<float> face_strength_field(const std::vector<float>& node_rest, const std::vector<index_t>& face_nodes,
                                       const std::vector<float>& corner_uv, const TearingOptions& options,
                                       const std::string& script);

}  // namespace tear
