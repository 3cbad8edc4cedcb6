// Every format tear has no reader of its own for (FBX, Collada, STL, ...) goes through assimp.
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

#include "io/assimp/confined_io_system.h"
#include "io/mesh/file_mesh.h"
#include "tear/error.h"
#include "tear/input_file.h"

namespace tear {
namespace {

Transform from_assimp(const aiMatrix4x4& a) {
  const ai_real* rows[4] = {a[0], a[1], a[2], a[3]};
  Transform t;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) t.m[r][c] = rows[r][c];
  }
  return t;
}

/// One placement of one aiMesh in the scene: a mesh referenced by two nodes is placed twice.
struct Placement {
  const aiMesh* mesh;
  const aiNode* node;
  Transform transform;
};

void collect_placements(const aiScene& scene, const aiNode& node, const Transform& parent, int depth,
                        std::vector<Placement>& placements) {
  const Transform transform = parent * from_assimp(node.mTransformation);
  for (unsigned i = 0; i < node.mNumMeshes; ++i) {
    if (node.mMeshes[i] < scene.mNumMeshes) placements.push_back({scene.mMeshes[node.mMeshes[i]], &node, transform});
  }
  if (depth > 1000) return;
  for (unsigned i = 0; i < node.mNumChildren; ++i) {
    if (node.mChildren[i]) collect_placements(scene, *node.mChildren[i], transform, depth + 1, placements);
  }
}

bool has_triangles(const aiMesh& mesh) {
  for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
    if (mesh.mFaces[f].mNumIndices == 3) return true;
  }
  return false;
}

/// assimp's messages name its own data structures ("aiScene::mNumMeshes is 0") and span lines;
/// ours say what is wrong with the file, on one line.
std::string describe_assimp_error(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  std::replace(text.begin(), text.end(), '\r', ' ');
  while (!text.empty() && (text.back() == ' ' || text.back() == '.')) text.pop_back();
  for (const char* empty : {"mNumMeshes is 0", "mNumFaces is 0", "mNumVertices is 0", "contains no faces",
                            "No meshes remaining", "has no faces", "is empty", "too small"}) {
    if (text.find(empty) != std::string::npos) return "holds no triangles";
  }
  if (text.find("No suitable reader found") != std::string::npos ||
      text.find("Unable to open file") != std::string::npos) {
    return "not a mesh file tear can read (its format is unknown or it is not a mesh)";
  }
  if (text.find("out of range") != std::string::npos || text.find("Invalid") != std::string::npos ||
      text.find("invalid") != std::string::npos) {
    return "malformed: " + text;
  }
  // Whatever else assimp says, without the names of its structures.
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    if (text.compare(i, 2, "ai") == 0 && i + 2 < text.size() && std::isupper(static_cast<unsigned char>(text[i + 2]))) {
      while (i < text.size() && text[i] != ' ') ++i;
      out += "the file";
      continue;
    }
    out += text[i++];
  }
  return "cannot read: " + out;
}

/// Keeps the placements whose mesh or node is named `mesh_name`; none is an input error listing the
/// names there are.
void keep_named(const std::string& path, const std::string& mesh_name, std::vector<Placement>& placements) {
  std::vector<std::string> names;
  for (const Placement& p : placements) {
    append_name(names, p.mesh->mName.C_Str());
    append_name(names, p.node->mName.C_Str());
  }
  placements.erase(std::remove_if(placements.begin(), placements.end(),
                                  [&](const Placement& p) {
                                    return mesh_name != p.mesh->mName.C_Str() && mesh_name != p.node->mName.C_Str();
                                  }),
                   placements.end());
  if (placements.empty()) throw no_mesh_named(path, mesh_name, names);
}

}  // namespace

FileMesh read_assimp_file(const std::string& path, const std::string& mesh_name) {
  Assimp::Importer importer;
  // Every file assimp opens goes through here: the mesh, and the files it names only inside its
  // folder (the importer owns the handler).
  auto* files = new ConfinedIoSystem(path, max_input_bytes());
  importer.SetIOHandler(files);
  // Points and lines are of no use to cloth; SortByPType moves them into meshes dropped here.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  // No JoinIdenticalVertices: it would merge corners and lose per-corner UVs and normals; weld_nodes
  // restores the topology instead. No PreTransformVertices: it loses the node names that select
  // meshes, so node transforms are applied here.
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_ValidateDataStructure);
  if (!scene) {
    // A file it names and may not read is the likely cause: said first.
    if (!files->refused().empty())
      throw input_error(path, "cannot be read without " + files->refused() +
                                  ", which it names: " + files->refused_why() + ", not opened (" +
                                  describe_assimp_error(importer.GetErrorString()) + ")");
    throw input_error(path, describe_assimp_error(importer.GetErrorString()));
  }
  if (!scene->mRootNode) throw input_error(path, "holds no triangles");

  std::vector<Placement> placements;
  collect_placements(*scene, *scene->mRootNode, Transform(), 0, placements);
  placements.erase(std::remove_if(placements.begin(), placements.end(),
                                  [](const Placement& p) { return !p.mesh || !has_triangles(*p.mesh); }),
                   placements.end());
  if (placements.empty()) throw input_error(path, "holds no triangles");

  if (!mesh_name.empty()) keep_named(path, mesh_name, placements);

  bool with_uv = false, with_normals = false;
  for (const Placement& p : placements) {
    with_uv = with_uv || p.mesh->HasTextureCoords(0);
    with_normals = with_normals || p.mesh->HasNormals();
  }
  FileMesh out;
  std::vector<float> position, normal, uv;
  std::vector<index_t> triangles;
  for (const Placement& p : placements) {
    const aiMesh& mesh = *p.mesh;
    position.clear();
    normal.clear();
    uv.clear();
    triangles.clear();
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      position.insert(position.end(), {mesh.mVertices[v].x, mesh.mVertices[v].y, mesh.mVertices[v].z});
      if (mesh.HasNormals()) normal.insert(normal.end(), {mesh.mNormals[v].x, mesh.mNormals[v].y, mesh.mNormals[v].z});
      if (mesh.HasTextureCoords(0)) uv.insert(uv.end(), {mesh.mTextureCoords[0][v].x, mesh.mTextureCoords[0][v].y});
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;
      for (int k = 0; k < 3; ++k) {
        if (face.mIndices[k] >= mesh.mNumVertices) throw input_error(path, "a face index is out of range");
        triangles.push_back(static_cast<index_t>(face.mIndices[k]));
      }
    }
    if (out.mesh.node_pos.size() / 3 + mesh.mNumVertices > max_index_count ||
        out.mesh.face_nodes.size() + triangles.size() > max_index_count) {
      throw input_error(path, "too large: more than 2^31 vertices or face corners");
    }
    PlacedTriangles placed;
    placed.vertex_count = static_cast<index_t>(mesh.mNumVertices);
    placed.vertex_pos = position.data();
    placed.vertex_normal = normal.empty() ? nullptr : normal.data();
    placed.vertex_uv = uv.empty() ? nullptr : uv.data();
    placed.triangles = &triangles;
    placed.transform = p.transform;
    append_placed(placed, with_uv, with_normals, false, false, out);
  }
  return out;
}

}  // namespace tear
