// tear: the files assimp may open while it reads a mesh: the mesh itself, and the files the mesh
// names (an OBJ's materials, a glTF's buffers, a scene's parts) only as `confine_file` allows
// them, so that nothing outside the mesh's folder is ever opened (docs/io.md, *Files a mesh
// names*). Example: reading `shots/a/cloth.gltf`, assimp's `shots/a/cloth.bin` is opened;
// `shots/a/../b.bin`, `/etc/passwd` and a FIFO at `shots/a/f.bin` are refused, never opened, and
// assimp fails ("could not open referenced file") or reads on without them.
// Only for read_assimp.cpp.
#pragma once

#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>

#include <cstdint>
#include <string>

namespace tear {

/// An `Assimp::IOSystem` that reads, and never writes, creates, removes or changes folders:
///
/// - the mesh, at the path given (`mesh_path`), as it was given;
/// - any other path assimp asks for only when it is `<folder of mesh_path>/<name>` with `name`
///   allowed by `confine_file` (relative, no `..`, no scheme, resolving, links followed, to a
///   regular file in the folder or below it);
///
/// each opened without blocking and read only when `fstat` says a regular file of at most
/// `max_bytes` (`--max-input-bytes`). Whatever is refused is never opened; the first refused path
/// is kept for the message (`refused`).
class ConfinedIoSystem final : public Assimp::IOSystem {
 public:
  ConfinedIoSystem(std::string mesh_path, std::uint64_t max_bytes);

  bool Exists(const char* file) const override;
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char* file, const char* mode = "rb") override;
  void Close(Assimp::IOStream* stream) override;
  bool CreateDirectory(const std::string&) override { return false; }
  bool ChangeDirectory(const std::string&) override { return false; }
  bool DeleteFile(const std::string&) override { return false; }

  /// The first path asked for and refused ("" when none), relative to the mesh's folder where
  /// assimp put it there ("../b.bin", "/etc/passwd"), and why: "outside the mesh's folder", "not
  /// a regular file in the mesh's folder or below it", "larger than --max-input-bytes (N bytes)".
  const std::string& refused() const { return refused_; }
  const std::string& refused_why() const { return refused_why_; }

 private:
  /// The path to open for `file`, or "" (with `why` set) when it may not be opened.
  std::string allowed(const std::string& file, std::string& why) const;
  void refuse(const std::string& file, const std::string& why) const;

  /// `file` as messages show it: without the mesh's folder in front.
  std::string shown(const std::string& file) const;

  std::string mesh_path_, folder_;
  std::uint64_t max_bytes_;
  mutable std::string refused_, refused_why_;
};

}  // namespace tear
