// tear: the frames of a sequence on disk, found by scanning the folder of its pattern.
//
// Example: out/ holds f.0001.ply, f.0002.ply, f.0010.ply, f.1.ply and notes.txt;
//   find_frames(FramePattern("out/f.####.ply")) -> {1, 2, 10}   (f.1.ply is not how #### writes 1)
#pragma once

#include <vector>

#include "tear/frame_path.h"

namespace tear {

/// The frame numbers `n` for which `pattern.path(n)` names an existing file, ascending.
///
/// The placeholders must all lie in the file name (not in a folder of the path): the folder is
/// listed once and each name is matched against the pattern, a frame counting only when the
/// pattern writes its number exactly that way (padding included). Throws a usage `Error` when the
/// pattern has no placeholder or one in a folder, and an input `Error` naming the pattern when its
/// folder cannot be listed.
std::vector<int> find_frames(const FramePattern& pattern);

}  // namespace tear
