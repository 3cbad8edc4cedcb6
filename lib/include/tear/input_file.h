// tear: reading an input file safely: a regular file only, its size known before reading and
// within a limit, never a blocking read (docs/io.md, *Bad input*; docs/cli.md, --max-input-bytes).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace tear {

/// The default of `--max-input-bytes`: 4 GiB.
constexpr std::uint64_t default_max_input_bytes = std::uint64_t(4) << 30;

/// The largest input file any reader of this process accepts (mesh, glTF buffer, cut script,
/// checkpoint, `tear diff` file). Process-wide; the CLI sets it from `--max-input-bytes`.
std::uint64_t max_input_bytes();
void set_max_input_bytes(std::uint64_t bytes);

/// Checks that `path` names a regular file (symlinks followed) of at most `limit` bytes, without
/// opening it for long and without reading it; returns its size. `what` names the file's role in
/// messages ("the mesh", "the cut script"). Throws an input `Error` naming `path` otherwise: a
/// missing file, a folder, a FIFO, a device, a socket, or a file over the limit.
std::uint64_t check_input_file(const std::string& path, const std::string& what,
                               std::uint64_t limit = max_input_bytes());

/// The whole of `path`, checked as `check_input_file` does on the descriptor it reads from. The
/// file is opened without blocking (a FIFO put there after the check does not hang the read), and
/// exactly the size `fstat` gave is read.
std::string read_input_file(const std::string& path, const std::string& what,
                            std::uint64_t limit = max_input_bytes());

/// Whether a file named inside another file (a glTF's buffer, a script's strength map) is one that
/// may be read: `name` must be a relative path (no URL scheme such as `file:`, not absolute, no
/// `..` component) that resolves, symbolic links followed, to a regular file inside `folder` or
/// below it ("" is the current folder). Example: folder "shots/a", name "maps/weak.png" is
/// allowed when shots/a/maps/weak.png is a file; "../b/weak.png" and "/etc/passwd" are not.
enum class Confined { ok, not_relative, goes_up, not_a_file_inside };
/// `path` gets the file's resolved path, the one to open, when the answer is `ok`. Nothing is opened.
Confined confine_file(const std::string& folder, const std::string& name, std::string& path);

/// What a file of mode `st_mode` is, for messages: "a directory", "a FIFO", "a character device", ...
std::string file_kind(unsigned mode);

/// How deep arrays and objects nest in JSON `text` of `size` bytes (strings skipped), counted
/// before parsing: parsers recurse and allocate per level, so a small file of `[[[[...` would
/// overflow the stack. Example: `{"a": [[1], 2]}` nests 3 deep.
std::size_t json_nesting_depth(const char* text, std::size_t size);

}  // namespace tear
