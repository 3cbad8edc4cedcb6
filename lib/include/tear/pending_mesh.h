// tear: a frame's mesh on its way from the backend to the host.
#pragma once

#include <memory>

#include "tear/mesh.h"

namespace tear {

/// A mesh that `take` hands over once it is on the host. `Cloth::mesh_later` returns one whose
/// copy is queued behind the backend's work and runs beside the next frame's (on CUDA: the frame
/// copied within the device, then to page-locked host memory on a copy stream of its own), so the
/// thread that runs the frames hands a frame to the writer without waiting for the copy, and
/// `take`, on a writer thread, waits for it. It can also hold a mesh already on the host.
///
/// Movable, not copyable; `take` may be called once, on any one thread.
class PendingMesh {
 public:
  /// Where the mesh comes from: `take` waits for it and builds the mesh, once.
  class Source {
   public:
    virtual ~Source() = default;
    virtual Mesh take() = 0;
  };

  PendingMesh();  ///< an empty mesh
  explicit PendingMesh(Mesh mesh);
  explicit PendingMesh(std::unique_ptr<Source> source);
  ~PendingMesh();
  PendingMesh(PendingMesh&&) noexcept;
  PendingMesh& operator=(PendingMesh&&) noexcept;

  /// Waits for the copy and returns the mesh; an empty mesh when called again.
  Mesh take();

 private:
  Mesh mesh_;
  std::unique_ptr<Source> source_;
};

}  // namespace tear
