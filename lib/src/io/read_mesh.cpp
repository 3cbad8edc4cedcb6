#include "tear/read_mesh.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "tear/error.h"

namespace tear {
namespace {

/// A row-major 4x4 affine transform in double precision (assimp's node transforms are float).
struct Transform {
  double m[4][4];

  static Transform from(const aiMatrix4x4& a) {
    const ai_real* rows[4] = {a[0], a[1], a[2], a[3]};
    Transform t;
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) t.m[r][c] = rows[r][c];
    }
    return t;
  }

  Transform operator*(const Transform& o) const {
    Transform t;
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) {
        t.m[r][c] = m[r][0] * o.m[0][c] + m[r][1] * o.m[1][c] + m[r][2] * o.m[2][c] + m[r][3] * o.m[3][c];
      }
    }
    return t;
  }

  bool is_identity() const {
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) {
        if (m[r][c] != (r == c ? 1.0 : 0.0)) return false;
      }
    }
    return true;
  }

  double linear_determinant() const {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  }
};

/// One placement of one aiMesh in the scene: a mesh referenced by two nodes is placed twice.
struct Placement {
  const aiMesh* mesh;
  const aiNode* node;
  Transform transform;
};

void collect_placements(const aiScene& scene, const aiNode& node, const Transform& parent,
                        std::vector<Placement>& placements) {
  const Transform transform = parent * Transform::from(node.mTransformation);
  for (unsigned i = 0; i < node.mNumMeshes; ++i) {
    if (node.mMeshes[i] < scene.mNumMeshes) placements.push_back({scene.mMeshes[node.mMeshes[i]], &node, transform});
  }
  for (unsigned i = 0; i < node.mNumChildren; ++i) {
    if (node.mChildren[i]) collect_placements(scene, *node.mChildren[i], transform, placements);
  }
}

bool has_triangles(const aiMesh& mesh) {
  for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
    if (mesh.mFaces[f].mNumIndices == 3) return true;
  }
  return false;
}

/// Assimp's messages can span lines; ours are one line.
std::string one_line(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  std::replace(text.begin(), text.end(), '\r', ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

void append_name(std::vector<std::string>& names, const std::string& name) {
  if (!name.empty() && std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
}

/// Appends the triangles of one placement. Each aiMesh vertex becomes a node; welding merges them.
void append_placement(const Placement& placement, bool with_uv, bool with_normals, Mesh& out) {
  const aiMesh& mesh = *placement.mesh;
  const Transform& t = placement.transform;
  const bool identity = t.is_identity();
  const double det = t.linear_determinant();
  // A mirroring transform turns counter-clockwise faces clockwise; swapping two corners restores it.
  const bool mirrored = det < 0.0;
  // Normals go through the inverse transpose of the linear part: the cofactor matrix over det.
  double normal_matrix[3][3];
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      const int r1 = (r + 1) % 3, r2 = (r + 2) % 3, c1 = (c + 1) % 3, c2 = (c + 2) % 3;
      const double cofactor = t.m[r1][c1] * t.m[r2][c2] - t.m[r1][c2] * t.m[r2][c1];
      normal_matrix[r][c] = det != 0.0 ? cofactor / det : cofactor;
    }
  }

  const index_t base = out.node_count();
  for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
    const aiVector3D& p = mesh.mVertices[v];
    if (identity) {
      out.node_pos.insert(out.node_pos.end(), {p.x, p.y, p.z});
      continue;
    }
    for (int r = 0; r < 3; ++r) {
      out.node_pos.push_back(static_cast<float>(t.m[r][0] * p.x + t.m[r][1] * p.y + t.m[r][2] * p.z + t.m[r][3]));
    }
  }

  const bool mesh_uv = mesh.HasTextureCoords(0);
  const bool mesh_normals = mesh.HasNormals();
  for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
    const aiFace& face = mesh.mFaces[f];
    if (face.mNumIndices != 3) continue;
    for (int k = 0; k < 3; ++k) {
      const unsigned v = face.mIndices[mirrored && k > 0 ? 3 - k : k];
      out.face_nodes.push_back(base + static_cast<index_t>(v));
      if (with_uv) {
        const aiVector3D uv = mesh_uv ? mesh.mTextureCoords[0][v] : aiVector3D(0, 0, 0);
        out.corner_uv.insert(out.corner_uv.end(), {uv.x, uv.y});
      }
      if (with_normals) {
        aiVector3D n = mesh_normals ? mesh.mNormals[v] : aiVector3D(0, 0, 0);
        if (mesh_normals && !identity) {
          double m[3];
          for (int r = 0; r < 3; ++r) {
            m[r] = normal_matrix[r][0] * n.x + normal_matrix[r][1] * n.y + normal_matrix[r][2] * n.z;
          }
          const double length = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
          const double scale = length > 0.0 ? 1.0 / length : 0.0;
          n = aiVector3D(static_cast<float>(m[0] * scale), static_cast<float>(m[1] * scale),
                         static_cast<float>(m[2] * scale));
        }
        out.corner_normal.insert(out.corner_normal.end(), {n.x, n.y, n.z});
      }
    }
  }
}

}  // namespace

Mesh read_mesh(const std::string& path, const ReadOptions& options) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw input_error(path, "cannot read: is a directory");
  if (std::FILE* file = std::fopen(path.c_str(), "rb")) {
    std::fclose(file);
  } else {
    throw input_error(path, std::string("cannot read: ") + std::strerror(errno));
  }

  Assimp::Importer importer;
  // Points and lines are of no use to cloth; SortByPType moves them into meshes dropped here.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  // No JoinIdenticalVertices: it would merge corners and lose per-corner UVs and normals; weld_nodes
  // restores the topology instead. No PreTransformVertices: it loses the node names that select
  // meshes, so node transforms are applied here.
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_ValidateDataStructure);
  if (!scene) throw input_error(path, "cannot import: " + one_line(importer.GetErrorString()));
  if (!scene->mRootNode) throw input_error(path, "holds no triangles");

  std::vector<Placement> placements;
  collect_placements(*scene, *scene->mRootNode, Transform::from(aiMatrix4x4()), placements);
  placements.erase(std::remove_if(placements.begin(), placements.end(),
                                  [](const Placement& p) { return !p.mesh || !has_triangles(*p.mesh); }),
                   placements.end());
  if (placements.empty()) throw input_error(path, "holds no triangles");

  if (!options.mesh_name.empty()) {
    std::vector<std::string> names;
    for (const Placement& p : placements) {
      append_name(names, p.mesh->mName.C_Str());
      append_name(names, p.node->mName.C_Str());
    }
    placements.erase(std::remove_if(placements.begin(), placements.end(),
                                    [&](const Placement& p) {
                                      return options.mesh_name != p.mesh->mName.C_Str() &&
                                             options.mesh_name != p.node->mName.C_Str();
                                    }),
                     placements.end());
    if (placements.empty()) {
      std::string listed;
      for (const std::string& name : names) listed += (listed.empty() ? "'" : ", '") + name + "'";
      throw input_error(path, "no mesh named '" + options.mesh_name + "'; meshes in the file: " +
                                  (listed.empty() ? std::string("none with a name") : listed));
    }
  }

  bool with_uv = false, with_normals = false;
  for (const Placement& p : placements) {
    with_uv = with_uv || p.mesh->HasTextureCoords(0);
    with_normals = with_normals || p.mesh->HasNormals();
  }
  Mesh mesh;
  for (const Placement& p : placements) append_placement(p, with_uv, with_normals, mesh);

  weld_nodes(mesh, options.weld_tolerance);
  if (mesh.face_count() == 0) throw input_error(path, "holds no triangles (all are degenerate)");
  return mesh;
}

}  // namespace tear
