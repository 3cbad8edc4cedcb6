// tear: crack growth from tips over smoothed stretch (crack_growth.h): where tips advance, join and
// hold, and where a new crack starts.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "cloth/crack_geometry.h"
#include "cloth/crack_growth.h"

namespace tear {

using namespace crack;

double CrackField::choose_direction(const Tip& tip, const double* S, double limit, Vec3& d,
                                    std::vector<Vec3>& seam_path) const {
  // The candidate directions: across the principal direction, or along the warp or the weft, or
  // along a seam from the tip; the one whose opening stretch passes its limit by most.
  double best = 0;
  d = {0, 0, 0};
  const auto consider = [&](Vec3 dir, double stretch_across, double lim) {
    if (dot(dir, tip.forward) < 0) dir = scale(dir, -1);
    const double ratio = std::sqrt(std::max(stretch_across, 0.0)) / lim;
    if (ratio > best) {
      best = ratio;
      d = dir;
      return true;
    }
    return false;
  };
  if (options_.has_weave && !m_.corner_uv.empty()) {
    const index_t f = m_.topo.node_faces[m_.topo.node_face_offset[tip.node]];
    const auto& w = options_.weave.warp;
    const Vec3 warp = unit(in_plane(thread_direction(f, w[0], w[1]), tip.normal));
    const Vec3 weft = unit(in_plane(thread_direction(f, -w[1], w[0]), tip.normal));
    // A crack keeps to the thread it runs along unless the other one opens by a tenth more:
    // woven cloth tears along one thread, not in a staircase of both.
    const double keep_warp = std::abs(dot(warp, tip.forward)) >= std::abs(dot(weft, tip.forward)) ? 1.1 : 1.0;
    consider(warp, keep_warp * keep_warp * quad(S, cross(tip.normal, warp)), limit);
    consider(weft, (2.21 - keep_warp * keep_warp) * quad(S, cross(tip.normal, weft)),
             limit * options_.weave.weft_strength);
  } else {
    Vec3 r;
    const double lambda = principal(S, tip.normal, r);
    // Across the principal direction, turned halfway to the crack's own course: a crack
    // keeps its course against the noise of a coarse mesh and still turns where the stress does.
    Vec3 across = unit(cross(tip.normal, r));
    if (dot(across, tip.forward) < 0) across = scale(across, -1);
    consider(unit(add(across, tip.forward)), lambda, limit);
  }
  // Along a seam edge that leaves the tip forwards.
  for (index_t i = m_.topo.node_face_offset[tip.node]; i < m_.topo.node_face_offset[tip.node + 1]; ++i) {
    const index_t f = m_.topo.node_faces[i];
    for (int k = 0; k < 3; ++k) {
      const index_t e = m_.topo.face_edges[3 * f + k];
      if (!edge_seam_[e]) continue;
      const index_t a = m_.topo.edge_nodes[2 * e], b = m_.topo.edge_nodes[2 * e + 1];
      if (a != tip.node && b != tip.node) continue;
      const index_t other = a == tip.node ? b : a;
      const Vec3 dir = unit(in_plane(sub(rest(other), tip.at), tip.normal));
      if (dot(dir, tip.forward) < 0.5) continue;
      if (consider(dir, quad(S, cross(tip.normal, dir)), limit * options_.seam_strength))
        seam_path = {tip.at, rest(other)};
    }
  }
  return best;
}

bool CrackField::advance(const Tip& tip, const FaceTensors& T, std::vector<Vec3>& path, bool& joined,
                         double& ratio) const {
  // The disc lies ahead of the tip, where the crack would run: centred on the tip it would average
  // in the unloaded flanks of its own slit.
  double S[6], strength = 1;
  smoothed(add(tip.at, scale(tip.forward, 0.5 * options_.radius)), T, S, &strength);
  const double limit = options_.stretch * strength;
  Vec3 d{0, 0, 0};
  std::vector<Vec3> seam_path;
  const double best = choose_direction(tip, S, limit, d, seam_path);
  ratio = best;
  if (best <= 1) return false;
  // At least past the faces around the tip, so the cut crosses an edge at any resolution.
  double longest = 0;
  for (index_t i = m_.topo.node_face_offset[tip.node]; i < m_.topo.node_face_offset[tip.node + 1]; ++i) {
    const index_t f = m_.topo.node_faces[i];
    for (int k = 0; k < 3; ++k) longest = std::max(longest, norm(sub(rest(m_.face_nodes[3 * f + k]), tip.at)));
  }
  const double step = std::max(options_.step_m(), 1.5 * longest);
  const bool on_seam = !seam_path.empty() && dot(unit(sub(seam_path[1], seam_path[0])), d) > 0.999999;
  Vec3 q = on_seam ? seam_path[1] : add(tip.course, scale(d, step));
  // Aimed from the crack's line, the step still leaves the tip by half a step at least: a path
  // shorter than the faces at the tip snaps to nothing, and the tip would stay where it is.
  if (!on_seam && dot(sub(q, tip.at), d) < 0.5 * step) q = add(tip.at, scale(d, step));
  // Within `radius` of another crack or the border: join it the shortest way, unless that cuts off
  // a piece under `min_piece`.
  Vec3 b;
  index_t edge = -1;
  if (nearest_border(q, &d, std::max(options_.radius, step), tip.node, b, edge) ||
      nearest_border(tip.at, &d, std::max(options_.radius, step), tip.node, b, edge)) {
    // A border at the tip itself (the far flank of a crack that already ran through here): the
    // cloth is parted there, and a cut from the tip to itself would only cut slivers off.
    if (norm(sub(b, tip.at)) < 0.5 * longest) {
      ratio = 0;
      return false;
    }
    const Vec3 dir = unit(sub(b, tip.at));
    const Vec3 end = add(b, scale(dir, 0.02 * longest));  // just across: the far flank of a slit is there too
    // Not across cloth a pin holds (a clamp between the tip and the border): the tip runs on
    // along the clamp instead, below, to a border it can join.
    if (!crosses_held(tip.at, end, tip.normal)) {
      if (piece_cut_off(tip.node, b, edge) < options_.min_piece_m2(total_area_)) {
        ratio = 0;  // held: it cannot run on without cutting off a shred
        return false;
      }
      path = {tip.at, end};
      joined = true;
      return true;
    }
  }
  // Into cloth a pin holds: the tip turns along it (turn_from_held), or holds.
  if (crosses_held(tip.at, q, tip.normal)) {
    ratio = turn_from_held(tip, S, limit, step, d, q);
    if (ratio == 0) return false;
  }
  // A tip on the flank of its own slit end (a snapped cut leaves some) may aim across the slit
  // itself, which the joining above leaves out as its own border: held, the slit's end runs on.
  if (crosses_border(tip.node, tip.at, tip.normal, q)) {
    ratio = 0;
    return false;
  }
  path = {tip.at, q};
  joined = false;
  return true;
}

double CrackField::turn_from_held(const Tip& tip, const double* S, double limit, double step, Vec3& d, Vec3& q) const {
  // By the least angle (15° at a time, up to a right angle either way) at which the stretch across
  // still passes the limit, the larger of the two sides at that angle: a clamped cloth tears along
  // the clamp's edge, and the clamp stays whole.
  const Vec3 n = tip.normal, ahead = unit(in_plane(d, n)), side = cross(n, ahead);
  double turned = 0;
  for (int k = 1; k <= 6 && turned == 0; ++k)
    for (const double sign : {1.0, -1.0}) {
      const double angle = sign * k * pi / 12;
      const Vec3 dir = unit(add(scale(ahead, std::cos(angle)), scale(side, std::sin(angle))));
      const double r = std::sqrt(std::max(quad(S, cross(n, dir)), 0.0)) / limit;
      const Vec3 to = add(tip.at, scale(dir, step));
      if (r > 1 && r > turned && !crosses_held(tip.at, to, n)) {
        turned = r;
        d = dir;
        q = to;
      }
    }
  return turned;
}

bool CrackField::near_crack(const Vec3& p) const {
  // Away from the cracks made so far, and well away from their tips: the cloth ahead of a tip is
  // the tip's to tear, even while it waits for the stress to build up again after a step.
  for (index_t t : tips_)
    if (norm(sub(rest(t), p)) < 4 * options_.radius) return true;
  for (index_t e : border_edges_) {
    const index_t f = m_.topo.edge_faces[2 * e];
    const index_t k = m_.topo.face_edges[3 * f] == e ? 0 : m_.topo.face_edges[3 * f + 1] == e ? 1 : 2;
    if (!m_.corner_torn.empty() && !m_.corner_torn[3 * f + (k + 1) % 3]) continue;
    const Vec3 A = rest(m_.topo.edge_nodes[2 * e]), B = rest(m_.topo.edge_nodes[2 * e + 1]);
    if (std::min(norm(sub(A, p)), norm(sub(B, p))) < options_.radius) return true;
  }
  return false;
}

std::vector<index_t> CrackField::start_candidates(const std::vector<double>& stretch,
                                                  const std::vector<index_t>& loaded) const {
  const double start_limit = options_.start_stretch();
  std::vector<std::pair<double, index_t>> ranked;
  for (index_t f = 0; f < m_.topo.face_count; ++f) {
    const double s = m_.face_strength.empty() ? 1.0 : m_.face_strength[f];
    if (stretch[f] > start_limit * s &&
        !std::binary_search(loaded.begin(), loaded.end(), node_piece_[m_.face_nodes[3 * f]]))
      ranked.push_back({-stretch[f] / s, f});
  }
  // The most stretched face of each grid cell (a disc's size) is a candidate: every stretched
  // region gets a say, not only the sharpest corners of a jagged border.
  std::sort(ranked.begin(), ranked.end());
  std::vector<std::int64_t> seen;
  std::vector<index_t> kept;
  for (const auto& c : ranked) {
    const Vec3& p = face_centroid_[c.second];
    std::int64_t key = 0;
    for (int a = 0; a < 3; ++a) key = key * 2097152 + (static_cast<std::int64_t>(std::floor(p[a] / cell_)) & 2097151);
    const auto at = std::lower_bound(seen.begin(), seen.end(), key);
    if (at != seen.end() && *at == key) continue;
    seen.insert(at, key);
    kept.push_back(c.second);
  }
  return kept;
}

bool CrackField::seam_start(const FaceTensors& T, const std::vector<index_t>& loaded, double& best,
                            std::vector<Vec3>& path) const {
  // A seam that reaches the border opens from there, inwards along its edge, at its own limit.
  index_t seam_node = -1, seam_other = -1;
  for (index_t e = 0; e < m_.topo.edge_count && options_.seam_strength != 1; ++e) {
    if (!edge_seam_[e]) continue;
    for (int j = 0; j < 2; ++j) {
      const index_t n = m_.topo.edge_nodes[2 * e + j], other = m_.topo.edge_nodes[2 * e + 1 - j];
      if (border_next_[n] < 0 || border_next_[other] >= 0) continue;
      if (std::binary_search(loaded.begin(), loaded.end(), node_piece_[n]) || near_crack(rest(n))) continue;
      const index_t f = m_.topo.edge_faces[2 * e];
      const Vec3 along = unit(in_plane(sub(rest(other), rest(n)), face_normal_[f]));
      double S[6], strength = 1;
      smoothed(rest(n), T, S, &strength);
      const double ratio = std::sqrt(std::max(quad(S, cross(face_normal_[f], along)), 0.0)) /
                           (options_.start_stretch() * strength * options_.seam_strength);
      if (ratio > best) {
        best = ratio;
        seam_node = n;
        seam_other = other;
      }
    }
  }
  if (seam_node < 0) return false;
  const Vec3 a = rest(seam_node), b = rest(seam_other);
  path = {sub(a, scale(sub(b, a), 0.1)), b};
  return true;
}

bool CrackField::start(const FaceTensors& T, const std::vector<double>& stretch, const std::vector<index_t>& loaded,
                       std::vector<Vec3>& path) const {
  // The candidates over the start limit, the most stretched (over its limit) first.
  struct Candidate {
    double ratio;
    index_t face;
    Vec3 across;
  };
  std::vector<Candidate> over;
  for (const index_t f : start_candidates(stretch, loaded)) {
    const Vec3& p = face_centroid_[f];
    if (!may_start_[f]) continue;  // near_crack(p), computed once per mesh
    double S[6], strength = 1;
    smoothed(p, T, S, &strength);
    Vec3 r;
    const double ratio =
        std::sqrt(std::max(principal(S, face_normal_[f], r), 0.0)) / (options_.start_stretch() * strength);
    if (ratio > 1) over.push_back({ratio, f, unit(cross(face_normal_[f], r))});
  }
  std::stable_sort(over.begin(), over.end(), [](const Candidate& a, const Candidate& b) { return a.ratio > b.ratio; });
  double best = over.empty() ? 1 : over.front().ratio;
  if (seam_start(T, loaded, best, path)) return true;
  // The most stretched; the next where a clamp leaves it no way to start (start_path).
  for (const Candidate& c : over) {
    bool held = false;
    if (start_path(c.face, c.across, path, held)) return true;
    if (!held) break;
  }
  return false;
}

bool CrackField::start_path(index_t chosen, const Vec3& across, std::vector<Vec3>& path, bool& held) const {
  const Vec3 p = face_centroid_[chosen];
  double size = 0;
  for (int k = 0; k < 3; ++k) size = std::max(size, norm(sub(rest(m_.face_nodes[3 * chosen + k]), p)));
  // An interior crack opens only where a crossing has a cut line on both sides: three crossings at
  // least, so the slit is some four faces long at any resolution. Near the border, it starts there.
  // A start that would cross a border (another crack; near a corner, the cloth's edge) is
  // shortened until it does not: what it would cut off there is for its tips to decide, against
  // `min_piece`, as they come near.
  const Vec3& normal = face_normal_[chosen];
  // From the border where it is near and the crack runs off it (along `d`), else a slit about p.
  Vec3 b, d = across;
  index_t edge = -1;
  bool from_border = false;
  if (nearest_border(p, nullptr, options_.radius, -1, b, edge)) {
    const Vec3 inward = unit(sub(p, b));
    from_border = std::abs(dot(across, inward)) > 0.3;
    if (from_border && dot(across, inward) < 0) d = scale(across, -1);
  }
  // An open end within a face of a border would snap onto it: each is tested a face further on.
  // A start from the border that would run into cloth a pin holds (a clamp between p and the
  // border) opens as a slit about p instead.
  const double longest_step = std::max(options_.step_m(), 7 * size);
  held = false;
  if (from_border)
    for (double step = longest_step; step >= 3 * size; step *= 0.5) {
      path = {sub(b, scale(d, size)), add(b, scale(d, step))};
      if (crosses_held(path.front(), path.back(), normal)) {
        held = true;
        continue;
      }
      if (!crosses_border(-1, add(b, scale(d, 0.05 * size)), normal, add(path.back(), scale(d, size)))) return true;
    }
  if (!from_border || held)
    for (double step = longest_step; step >= 3 * size; step *= 0.5) {
      path = {sub(p, scale(d, step / 2)), add(p, scale(d, step / 2))};
      if (crosses_held(path.front(), path.back(), normal)) {
        held = true;
        continue;
      }
      if (!crosses_border(-1, sub(path.front(), scale(d, size)), normal, add(path.back(), scale(d, size)))) return true;
    }
  return false;
}

bool CrackField::make_tip(index_t n, Tip& out) const {
  Tip tip{n, rest(n), {0, 0, 0}, {0, 0, 0}, rest(n)};
  Vec3 normal{0, 0, 0};
  for (index_t i = m_.topo.node_face_offset[n]; i < m_.topo.node_face_offset[n + 1]; ++i) {
    const index_t f = m_.topo.node_faces[i];
    normal = add(normal, scale(face_normal_[f], face_area_[f]));
  }
  tip.normal = unit(normal);
  // The crack's course: the line fitted through its slit over four radii back along both flanks,
  // not its last edge. Snapping moves each tip off the line by a fraction of an edge; aiming the
  // next step from the line keeps those offsets from adding up.
  std::vector<Vec3> slit{tip.at};
  Vec3 back{0, 0, 0};
  for (const auto* walk : {&border_prev_, &border_next_}) {
    index_t m = n;
    double walked = 0;
    for (index_t i = 0; i < m_.topo.node_count && walked < 4 * radius_; ++i) {
      const index_t next = (*walk)[m];
      if (next < 0 || next == n) break;
      // Along the slit only: the cloth's own border beyond it is not the crack's course.
      if (!border_torn_[walk == &border_next_ ? m : next]) break;
      const bool near = walked < radius_;
      walked += norm(sub(rest(next), rest(m)));
      m = next;
      slit.push_back(rest(m));
      if (near) back = add(back, unit(sub(rest(m), tip.at)));
    }
  }
  Vec3 centre{0, 0, 0};
  for (const Vec3& p : slit) centre = add(centre, scale(p, 1.0 / slit.size()));
  const Vec3 b1 = any_tangent(tip.normal), b2 = cross(tip.normal, b1);
  double c11 = 0, c12 = 0, c22 = 0;
  for (const Vec3& p : slit) {
    const Vec3 q = sub(p, centre);
    c11 += dot(q, b1) * dot(q, b1), c12 += dot(q, b1) * dot(q, b2), c22 += dot(q, b2) * dot(q, b2);
  }
  const double half = 0.5 * (c11 - c22), lambda = 0.5 * (c11 + c22) + std::sqrt(half * half + c12 * c12);
  Vec3 line = std::abs(lambda - c22) + std::abs(c12) > 1e-300 ? unit(add(scale(b1, lambda - c22), scale(b2, c12)))
                                                              : unit(in_plane(scale(back, -1), tip.normal));
  if (dot(line, back) > 0) line = scale(line, -1);
  tip.course = add(centre, scale(line, dot(sub(tip.at, centre), line)));
  if (norm(sub(tip.course, tip.at)) > 0.5 * radius_) tip.course = tip.at;  // a kinked slit: no line
  back = scale(line, -1);
  tip.forward = unit(scale(in_plane(back, tip.normal), -1));
  out = tip;
  return norm(tip.forward) > 0;
}

double CrackField::largest_tip_ratio(const std::vector<float>& node_pos) const {
  const FaceTensors T = face_tensors(node_pos);
  double largest = 0;
  for (index_t n : tips_) {
    Tip tip;
    if (!make_tip(n, tip)) continue;
    std::vector<Vec3> path;
    bool joined = false;
    double ratio = 0;
    advance(tip, T, path, joined, ratio);
    largest = std::max(largest, ratio);
  }
  return largest;
}

void CrackField::mark_may_start() {
  // near_crack's rule for every face's centroid, over the grid instead of every face: the faces
  // within four radii of a tip and within a radius of a node of a torn border edge (each node once:
  // a border node ends two such edges). The queries run on the host's threads; each only clears
  // flags, so their order does not matter.
  // No crack starts in cloth a pin holds whole.
  may_start_.assign(m_.topo.face_count, 1);
  if (any_held_)
    for (index_t f = 0; f < m_.topo.face_count; ++f) may_start_[f] = !face_held(f);
  std::vector<std::pair<index_t, double>> queries;
  for (index_t t : tips_) queries.emplace_back(t, 4 * options_.radius);
  std::vector<std::uint8_t> seen(m_.topo.node_count, 0);
  for (index_t e : border_edges_) {
    const index_t f = m_.topo.edge_faces[2 * e];
    const index_t c = m_.topo.face_edges[3 * f] == e ? 0 : m_.topo.face_edges[3 * f + 1] == e ? 1 : 2;
    if (!m_.corner_torn.empty() && !m_.corner_torn[3 * f + (c + 1) % 3]) continue;
    for (int j = 0; j < 2; ++j) {
      const index_t n = m_.topo.edge_nodes[2 * e + j];
      if (!seen[n]) queries.emplace_back(n, options_.radius);
      seen[n] = 1;
    }
  }
  const std::int64_t count = static_cast<std::int64_t>(queries.size());
#pragma omp parallel for schedule(dynamic, 16)
  for (std::int64_t q = 0; q < count; ++q) {
    const Vec3 p = rest(queries[q].first);
    const double r = queries[q].second;
    faces_near(p, r, [&](index_t g) {
      if (norm(sub(p, face_centroid_[g])) < r) {
#pragma omp atomic write
        may_start_[g] = 0;
      }
    });
  }
}

CrackProbes CrackField::probes() const {
  CrackProbes out;
  const auto add_probe = [&](const Vec3& centre, const Vec3& normal, double limit, double gain) {
    const std::vector<index_t> faces = disc(centre);
    out.faces.insert(out.faces.end(), faces.begin(), faces.end());
    out.offsets.push_back(static_cast<index_t>(out.faces.size()));
    out.normal.insert(out.normal.end(), normal.begin(), normal.end());
    out.limit.push_back(limit);
    out.gain.push_back(gain);
  };
  // Tips (advance): the disc ahead of the tip; the weakest of the limits its directions meet (the
  // warp's, the weft's, a seam's); a crack that keeps to its thread sees up to 1.1 times the stretch.
  const double weft = options_.has_weave ? options_.weave.weft_strength : 1.0;
  const double k = std::min({1.0, weft, options_.seam_strength});
  for (index_t n : tips_) {
    Tip tip;
    if (!make_tip(n, tip)) continue;
    add_probe(add(tip.at, scale(tip.forward, 0.5 * options_.radius)), tip.normal, options_.stretch * k,
              options_.has_weave && !m_.corner_uv.empty() ? 1.1 : 1.0);
  }
  // Seams that may open from the border (seam_start), loaded pieces or not.
  for (index_t e = 0; e < m_.topo.edge_count && options_.seam_strength != 1; ++e) {
    if (!edge_seam_[e]) continue;
    for (int j = 0; j < 2; ++j) {
      const index_t n = m_.topo.edge_nodes[2 * e + j], other = m_.topo.edge_nodes[2 * e + 1 - j];
      if (border_next_[n] < 0 || border_next_[other] >= 0 || near_crack(rest(n))) continue;
      add_probe(rest(n), face_normal_[m_.topo.edge_faces[2 * e]], options_.start_stretch() * options_.seam_strength,
                1.0);
    }
  }
  out.may_start = may_start_;
  out.cell_key = cell_key_;
  out.cell_face = cell_face_;
  out.cell = cell_;
  out.radius = radius_;
  return out;
}

bool CrackField::may_cut(const CrackProbes& probes, const std::vector<double>& sums, double start_ratio) const {
  // A thousandth of margin: the backend's sums may round apart from the host's.
  constexpr double margin = 0.999;
  if (start_ratio > margin) return true;
  for (std::size_t p = 0; p < probes.count(); ++p) {
    const double* sum = &sums[8 * p];
    if (!(sum[7] > 0)) continue;  // smoothed() gives no stretch there
    double S[6];
    for (int k = 0; k < 6; ++k) S[k] = sum[k] / sum[7];
    const double strength = sum[6] / sum[7];
    Vec3 r;
    const Vec3 normal{probes.normal[3 * p], probes.normal[3 * p + 1], probes.normal[3 * p + 2]};
    const double ratio =
        probes.gain[p] * std::sqrt(std::max(principal(S, normal, r), 0.0)) / (probes.limit[p] * strength);
    if (ratio > margin) return true;
  }
  return false;
}

CrackPlan CrackField::plan(const std::vector<float>& node_pos) const {
  CrackPlan plan;
  const FaceTensors T = face_tensors(node_pos);
  std::vector<std::vector<Vec3>> paths;
  std::vector<index_t> loaded;  // pieces with a tip free to run that bears most of its limit
  std::vector<index_t> joining;  // the tips that join a border this substep
  for (index_t n : tips_) {
    if (static_cast<int>(paths.size()) >= options_.max_faces_per_step) break;
    Tip tip;
    if (!make_tip(n, tip)) continue;
    std::vector<Vec3> path;
    bool joined = false;
    double ratio = 0;
    const bool moves = advance(tip, T, path, joined, ratio);
    if (ratio > 0.6) loaded.push_back(node_piece_[n]);
    if (!moves) continue;
    // Two cracks of one substep that come near each other could cut off what neither would alone:
    // the later waits for the next substep, when it sees the first as a crack.
    bool clear = true;
    for (const auto& other : paths)
      clear = clear && segment_distance(path.front(), path.back(), other.front(), other.back()) >= options_.radius;
    // Nor do two joins of one crack's tips (tips on one border): each sees the crack as a border of
    // its own, whose joining cuts nothing off, and together they could cut off a piece under
    // `min_piece`. The later waits, and then measures what the first has made.
    if (joined)
      for (index_t other : joining) clear = clear && !on_one_border(n, other);
    if (clear && joined) joining.push_back(n);
    if (clear) paths.push_back(std::move(path));
  }
  std::sort(loaded.begin(), loaded.end());
  {
    // A new crack only in a piece whose cracks bear little load: a loaded crack runs through its
    // piece and takes the load off it; a second crack there would break it twice, or cut a sliver
    // between the two.
    // Only where no tip moves: every face's stretch, for the candidates.
    if (paths.empty()) {
      T.compute_all();
      std::vector<double> stretch(m_.topo.face_count);
#pragma omp parallel for schedule(static)
      for (index_t f = 0; f < m_.topo.face_count; ++f) {
        Vec3 r;
        stretch[f] = std::sqrt(std::max(principal(T(f), face_normal_[f], r), 0.0));
      }
      std::vector<Vec3> path;
      if (start(T, stretch, loaded, path)) paths.push_back(std::move(path));
    }
  }
  for (const auto& path : paths) {
    // A straight rest-space cut in the plane of its start, projected along that plane's normal.
    const Vec3 d = unit(sub(path.back(), path.front()));
    Vec3 normal{0, 0, 0};
    faces_near(path.front(), options_.radius,
               [&](index_t f) { normal = add(normal, scale(face_normal_[f], face_area_[f])); });
    normal = unit(in_plane(normal, d));
    if (norm(normal) == 0) normal = any_tangent(d);
    const Vec3 v = cross(normal, d);
    CutLine line;
    line.source = CutLine::Source::node_rest;
    line.axis_u = d;
    line.axis_v = v;
    for (const Vec3& p : path) line.polyline.push_back({dot(p, d), dot(p, v)});
    for (std::size_t i = 1; i < path.size(); ++i) plan.length += norm(sub(path[i], path[i - 1]));
    plan.cuts.push_back(std::move(line));
    ++plan.events;
  }
  return plan;
}

}  // namespace tear
