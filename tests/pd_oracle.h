// The test oracle of the projective dynamics solver: the same model and step, built independently
// on the host in double precision, with each global step solved exactly by a sparse Cholesky
// factorisation (Eigen's SimplicialLDLT) instead of Jacobi iterations.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "tear/mesh.h"
#include "tear/simulation.h"

namespace tear::test {

class PdOracle {
 public:
  struct Constraint {
    std::vector<index_t> nodes;
    std::vector<double> coef;
    double weight = 0;
    double rest = 0;
  };

  PdOracle(const std::vector<index_t>& face_nodes, const std::vector<float>& node_rest, index_t node_count,
           const SimulationOptions& options, const std::vector<std::uint8_t>& node_pinned)
      : options_(options), node_count_(node_count), pinned_(node_pinned) {
    const auto rest = [&](index_t n) {
      return Eigen::Vector3d(node_rest[3 * n], node_rest[3 * n + 1], node_rest[3 * n + 2]);
    };
    const auto area = [&](index_t a, index_t b, index_t c) {
      return 0.5 * (rest(b) - rest(a)).cross(rest(c) - rest(a)).norm();
    };
    mass_.assign(node_count, 0.0);
    std::map<std::pair<index_t, index_t>, std::vector<index_t>> edge_opposite;  // edge -> opposite nodes
    std::map<std::pair<index_t, index_t>, double> edge_area;
    for (std::size_t f = 0; f < face_nodes.size() / 3; ++f) {
      const index_t* v = &face_nodes[3 * f];
      const double a = area(v[0], v[1], v[2]);
      for (int k = 0; k < 3; ++k) {
        mass_[v[k]] += options.density * a / 3;
        const index_t p = v[(k + 1) % 3], q = v[(k + 2) % 3];
        const auto key = std::make_pair(std::min(p, q), std::max(p, q));
        edge_opposite[key].push_back(v[k]);
        edge_area[key] += a / 3;
      }
    }
    const bool membrane = options.stretch_model_used() == StretchModel::membrane;
    if (membrane && options.stretch_stiffness > 0)
      for (std::size_t f = 0; f < face_nodes.size() / 3; ++f) {
        // The face's deformation gradient in an orthonormal frame T of its rest plane: F = X G with
        // X = [x₀ x₁ x₂] and G = P (Tᵀ E)⁻¹, E the rest edges x₁ − x₀, x₂ − x₀ and P the matrix
        // [−1 −1; 1 0; 0 1] that takes X to them.
        const index_t* v = &face_nodes[3 * f];
        Eigen::Matrix<double, 3, 2> e;
        e.col(0) = rest(v[1]) - rest(v[0]);
        e.col(1) = rest(v[2]) - rest(v[0]);
        const Eigen::Vector3d normal = e.col(0).cross(e.col(1));
        if (!(normal.norm() > 1e-8 * e.colwise().squaredNorm().maxCoeff())) continue;
        Eigen::Matrix<double, 3, 2> t;
        t.col(0) = e.col(0).normalized();
        t.col(1) = normal.normalized().cross(t.col(0));
        const Eigen::Matrix2d rest_edges = t.transpose() * e;
        Eigen::Matrix<double, 3, 2> p;
        p << -1, -1, 1, 0, 0, 1;
        membranes_.push_back(
            {{v[0], v[1], v[2]}, p * rest_edges.inverse(), options.stretch_stiffness * 0.375 * 0.5 * normal.norm()});
      }
    for (const auto& [edge, opposite] : edge_opposite) {
      const auto [a, b] = edge;
      const double len = (rest(b) - rest(a)).norm();
      if (len > 0 && options.stretch_stiffness > 0 && !membrane)
        constraints_.push_back({{a, b}, {1.0, -1.0}, options.stretch_stiffness * edge_area[edge] / (len * len), len});
      if (opposite.size() == 2 && options.bend_stiffness > 0) {
        // Unfold the hinge into the plane: the edge on the u axis, each opposite node at its
        // (foot, height) on its own side. The operator is the combination with Σk = 0 that
        // vanishes on that flat hinge, scaled so that k = 1/height at the opposite nodes.
        const Eigen::Vector3d e = (rest(b) - rest(a)) / len;
        double u[2], height[2];
        for (int i = 0; i < 2; ++i) {
          const Eigen::Vector3d r = rest(opposite[i]) - rest(a);
          u[i] = r.dot(e);
          height[i] = (r - u[i] * e).norm();
        }
        if (height[0] <= 1e-8 * len || height[1] <= 1e-8 * len) continue;
        const double k2 = 1 / height[0], k3 = 1 / height[1];
        const double k1 = -(k2 * u[0] + k3 * u[1]) / len;
        const double k0 = -(k1 + k2 + k3);
        Constraint c{{a, b, opposite[0], opposite[1]}, {k0, k1, k2, k3}, 0, 0};
        const double hinge_area = 0.5 * len * (height[0] + height[1]);
        c.weight = options.bend_stiffness * 3 * len * len / hinge_area;
        Eigen::Vector3d fold = Eigen::Vector3d::Zero();
        for (int j = 0; j < 4; ++j) fold += c.coef[j] * rest(c.nodes[j]);
        c.rest = fold.norm();
        constraints_.push_back(c);
      }
    }

    // The global matrix over the free nodes; pinned nodes are known values moved to the right side.
    free_index_.assign(node_count, -1);
    index_t free_count = 0;
    for (index_t n = 0; n < node_count; ++n)
      if (!pinned_[n]) free_index_[n] = free_count++;
    const double h = options.step_seconds();
    std::vector<Eigen::Triplet<double>> triplets;
    for (index_t n = 0; n < node_count; ++n)
      if (free_index_[n] >= 0) triplets.emplace_back(free_index_[n], free_index_[n], mass_[n] / (h * h));
    for (const Constraint& c : constraints_)
      for (std::size_t i = 0; i < c.nodes.size(); ++i)
        for (std::size_t j = 0; j < c.nodes.size(); ++j)
          if (free_index_[c.nodes[i]] >= 0 && free_index_[c.nodes[j]] >= 0)
            triplets.emplace_back(free_index_[c.nodes[i]], free_index_[c.nodes[j]], c.weight * c.coef[i] * c.coef[j]);
    for (const Membrane& m : membranes_)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          if (free_index_[m.nodes[i]] >= 0 && free_index_[m.nodes[j]] >= 0)
            triplets.emplace_back(free_index_[m.nodes[i]], free_index_[m.nodes[j]],
                                  m.weight * m.g.row(i).dot(m.g.row(j)));
    matrix_.resize(free_count, free_count);
    matrix_.setFromTriplets(triplets.begin(), triplets.end());
    solver_.compute(matrix_);
  }

  /// A face's membrane: F = [x₀ x₁ x₂] g, energy weight/2 ‖F − R‖², R F's nearest rotation.
  struct Membrane {
    std::array<index_t, 3> nodes;
    Eigen::Matrix<double, 3, 2> g;
    double weight = 0;
  };

  const std::vector<Constraint>& constraints() const { return constraints_; }
  const std::vector<Membrane>& membranes() const { return membranes_; }
  const std::vector<double>& node_mass() const { return mass_; }
  bool ok() const { return solver_.info() == Eigen::Success; }

  /// One frame: `substeps` implicit Euler steps, as PdSolver::step but in double precision, each
  /// running local/global iterations (the global step exact) until no node moves by more than
  /// `tolerance` metres in one iteration, or `max_iterations` of them.
  void step(std::vector<double>& pos, std::vector<double>& vel, double tolerance, int max_iterations) const {
    const double h = options_.step_seconds();
    const double velocity_scale = std::pow(1.0 - options_.damping, h);
    const Eigen::Vector3d g(options_.gravity[0], options_.gravity[1], options_.gravity[2]);
    const Eigen::Index free_count = matrix_.rows();
    for (int sub = 0; sub < options_.substeps; ++sub) {
      std::vector<Eigen::Vector3d> x(node_count_), s(node_count_);
      for (index_t n = 0; n < node_count_; ++n) {
        const Eigen::Vector3d xn(pos[3 * n], pos[3 * n + 1], pos[3 * n + 2]);
        const Eigen::Vector3d vn(vel[3 * n], vel[3 * n + 1], vel[3 * n + 2]);
        s[n] = pinned_[n] ? xn : Eigen::Vector3d(xn + h * vn + h * h * g);
        x[n] = s[n];
      }
      for (int it = 0; it < max_iterations; ++it) {
        Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(free_count, 3);
        for (index_t n = 0; n < node_count_; ++n)
          if (free_index_[n] >= 0) rhs.row(free_index_[n]) = (mass_[n] / (h * h)) * s[n].transpose();
        for (const Constraint& c : constraints_) {
          Eigen::Vector3d d = Eigen::Vector3d::Zero();
          for (std::size_t j = 0; j < c.nodes.size(); ++j) d += c.coef[j] * x[c.nodes[j]];
          const Eigen::Vector3d p = d.norm() > 0 ? Eigen::Vector3d(c.rest / d.norm() * d) : d;
          for (std::size_t i = 0; i < c.nodes.size(); ++i) {
            const index_t row = free_index_[c.nodes[i]];
            if (row < 0) continue;
            Eigen::Vector3d r = c.weight * c.coef[i] * p;
            for (std::size_t j = 0; j < c.nodes.size(); ++j)
              if (pinned_[c.nodes[j]]) r -= c.weight * c.coef[i] * c.coef[j] * x[c.nodes[j]];
            rhs.row(row) += r.transpose();
          }
        }
        for (const Membrane& m : membranes_) {
          Eigen::Matrix3d x3;
          for (int i = 0; i < 3; ++i) x3.col(i) = x[m.nodes[i]];
          const Eigen::Matrix<double, 3, 2> f = x3 * m.g;
          const Eigen::JacobiSVD<Eigen::Matrix<double, 3, 2>> svd(f, Eigen::ComputeFullU | Eigen::ComputeFullV);
          const Eigen::Matrix<double, 3, 2> r = svd.matrixU().leftCols<2>() * svd.matrixV().transpose();
          for (int i = 0; i < 3; ++i) {
            const index_t row = free_index_[m.nodes[i]];
            if (row < 0) continue;
            Eigen::Vector3d term = m.weight * r * m.g.row(i).transpose();
            for (int j = 0; j < 3; ++j)
              if (pinned_[m.nodes[j]]) term -= m.weight * m.g.row(i).dot(m.g.row(j)) * x[m.nodes[j]];
            rhs.row(row) += term.transpose();
          }
        }
        const Eigen::MatrixXd solution = solver_.solve(rhs);
        double change = 0;
        for (index_t n = 0; n < node_count_; ++n)
          if (free_index_[n] >= 0) {
            const Eigen::Vector3d next = solution.row(free_index_[n]).transpose();
            change = std::max(change, (next - x[n]).norm());
            x[n] = next;
          }
        if (change <= tolerance) break;
      }
      for (index_t n = 0; n < node_count_; ++n) {
        if (pinned_[n]) {
          for (int a = 0; a < 3; ++a) vel[3 * n + a] = 0;
          continue;
        }
        for (int a = 0; a < 3; ++a) {
          vel[3 * n + a] = velocity_scale * (x[n][a] - pos[3 * n + a]) / h;
          pos[3 * n + a] = x[n][a];
        }
      }
    }
  }

 private:
  SimulationOptions options_;
  index_t node_count_;
  std::vector<std::uint8_t> pinned_;
  std::vector<double> mass_;
  std::vector<Constraint> constraints_;
  std::vector<Membrane> membranes_;
  std::vector<index_t> free_index_;
  Eigen::SparseMatrix<double> matrix_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver_;
};

}  // namespace tear::test
