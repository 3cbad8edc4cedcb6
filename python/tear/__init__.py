"""tear: cut and tear triangle cloth meshes, on the GPU or the CPU, from Python.

The same library as the ``tear`` command line: the same readers and writers, the same checks and
the same messages. A run gives the same bytes from Python as from ``tear run``.

    import tear
    mesh = tear.read_mesh("cloth.obj")
    script = tear.Script.load("shot.json")
    for frame in tear.run(mesh, script, device="cpu"):
        frame.points        # (N, 3) float32, read-only, a view of the frame's buffer
        frame.write(f"out/cloth.{frame.number:04}.ply")

Errors are exceptions, one class per exit code of the command line (docs/cli.md): ``UsageError``
(1), ``BadInput`` (2), ``RuntimeFailure`` (3), ``Interrupted`` (4), all ``tear.Error``; their
message is what ``tear`` prints after ``tear: ``. docs/python.md is the reference.
"""

import json as _json
import os as _os

from . import _tear

__version__ = _tear.__version__

__all__ = [
    "__version__", "Error", "UsageError", "BadInput", "RuntimeFailure", "Interrupted",
    "Mesh", "Frame", "Script", "Cloth", "DeviceArray", "FrameIterator", "read_mesh", "run", "cuda_available",
]


class Error(Exception):
    """A failure of tear; ``exit_code`` is the exit code ``tear`` gives for it."""

    exit_code = 3


class UsageError(Error, ValueError):
    """An argument is wrong (exit code 1): a bad device, option value or output pattern."""

    exit_code = 1


class BadInput(Error):
    """A mesh or script is missing, malformed or unusable, or an output would overwrite an input
    (exit code 2). The message names the file and, for a script, the JSON key path."""

    exit_code = 2


class RuntimeFailure(Error):
    """The input was fine but the run failed (exit code 3): an output that cannot be written, a
    device error, out of memory, a diverging simulation."""

    exit_code = 3


class Interrupted(Error):
    """A run to files was stopped by SIGINT or SIGTERM after a whole frame (exit code 4); with a
    checkpoint, ``resume=True`` goes on from there."""

    exit_code = 4


_tear._set_error_classes(UsageError, BadInput, RuntimeFailure, Interrupted)

Mesh = _tear.Mesh
Frame = _tear.Frame
FrameIterator = _tear.FrameIterator
_ClothHandle = _tear.Cloth


def _fspath(path, what):
    try:
        return _os.fsdecode(_os.fspath(path))
    except TypeError:
        raise UsageError(f"{what}: expected a path, got {type(path).__name__}") from None


def _mesh_write(self, path, *, up_axis=None, meters_per_unit=None):
    """Writes the mesh with the writer of the path's extension, as ``tear run`` does: ``.obj``,
    ``.ply``, ``.gltf``, ``.glb``, or ``.usda``/``.usd`` (one layer holding this frame). A frame
    number placeholder (``####``, ``{frame:04}``) takes the frame's number. Atomic; folders are
    created."""
    number = getattr(self, "number", 1)
    self._write(_fspath(path, "path"), number, up_axis, meters_per_unit)


def _mesh_repr(self):
    return f"<tear.{type(self).__name__} {self.node_count} nodes, {self.face_count} faces>"


def _frame_repr(self):
    return f"<tear.Frame {self.number}: {self.node_count} nodes, {self.face_count} faces>"


Mesh.write = _mesh_write
Mesh.__repr__ = _mesh_repr
Frame.__repr__ = _frame_repr


def cuda_available():
    """True when this build has the CUDA backend and a usable GPU."""
    return _tear._cuda_available()


def read_mesh(path, *, weld_tolerance=0.0, mesh_name=None, weld=True, device="auto"):
    """Reads a mesh as ``tear run`` does (``--weld-tolerance``, ``--mesh-name``, ``--no-weld``):
    OBJ, PLY, glTF/GLB by tear's readers, other formats through assimp. Raises ``BadInput`` for a
    missing, malformed or unusable file, ``UsageError`` for a bad tolerance or device."""
    return _tear._read_mesh(_fspath(path, "path"), float(weld_tolerance), mesh_name or "", bool(weld), device)


class Script:
    """A parsed and checked cut script (docs/cut-script.md).

    ``Script.load(path)`` reads a file; ``Script(data)`` takes the same schema as a ``dict`` (or
    its JSON text), named ``name`` in messages. Errors are ``BadInput`` with the CLI's message
    (``shot.json: cuts[0].frame: ...``).
    """

    __slots__ = ("_handle",)

    def __init__(self, data, *, name="script"):
        if isinstance(data, _tear.Script):
            self._handle = data
            return
        text = data if isinstance(data, str) else _json.dumps(data)
        self._handle = _tear._parse_script(text, name)

    @classmethod
    def load(cls, path):
        """Reads and checks the script file at ``path``."""
        return cls(_tear._read_script(_fspath(path, "path")))

    frames = property(lambda self: self._handle.frames, doc="Frames of the run.")
    snap = property(lambda self: self._handle.snap, doc="The script's snap tolerance.")
    version = property(lambda self: self._handle.version, doc="The script's format version.")
    path = property(lambda self: self._handle.path, doc="The file (or name) used in messages.")
    cut_count = property(lambda self: self._handle.cut_count, doc="Cuts of the script.")
    simulated = property(lambda self: self._handle.simulated, doc="True when it has a simulation block.")
    fps = property(lambda self: self._handle.fps, doc="The simulation's frames per second (24 without).")

    def __repr__(self):
        return f"<tear.Script {self.path!r}: {self.frames} frames, {self.cut_count} cuts>"


def _as_mesh(mesh, device):
    if isinstance(mesh, Mesh):
        return mesh
    return read_mesh(mesh, device=device)


def _as_script(script):
    if isinstance(script, Script):
        return script
    if isinstance(script, dict):
        return Script(script)
    return Script.load(script)


def run(mesh, script, *, device="auto", start_frame=1, frames=None, output=None, report=None,
        up_axis=None, meters_per_unit=None, checkpoint=None, checkpoint_every=1, resume=False,
        writer_threads=0):
    """Runs ``script`` on ``mesh`` (a ``Mesh`` or a path; a ``Script``, a dict or a path).

    Without ``output``: returns an iterator of ``Frame``s, one per frame (``frames`` limits them),
    numbered from ``start_frame``, each the mesh ``tear run`` would write for it. Every check of
    ``tear run`` is made before it returns.

    With ``output`` (a pattern such as ``"out/f.####.ply"``, or a ``.usda`` layer): writes the whole
    run exactly as ``tear run MESH SCRIPT -o OUTPUT`` does (``report``, ``up_axis``,
    ``meters_per_unit``, ``checkpoint``, ``checkpoint_every``, ``resume``, ``writer_threads`` as its
    flags) and returns ``{"frames", "faces", "wall_ms"}``. SIGINT or SIGTERM stops it after a whole
    frame with ``Interrupted``.

    The GIL is released while the library works.
    """
    if isinstance(start_frame, bool) or not isinstance(start_frame, int) or start_frame < 0:
        raise UsageError(f"start_frame: expected an integer >= 0, got {start_frame!r}")
    if frames is not None and (isinstance(frames, bool) or not isinstance(frames, int) or frames < 1):
        raise UsageError(f"frames: expected an integer >= 1, got {frames!r}")
    if output is None:
        for name, value in (("report", report), ("up_axis", up_axis), ("meters_per_unit", meters_per_unit),
                            ("checkpoint", checkpoint)):
            if value is not None:
                raise UsageError(f"{name}: applies to a run with output only")
        mesh = _as_mesh(mesh, device)
        script = _as_script(script)
        return _tear._run_frames(mesh, script._handle, device, start_frame, frames or 0)
    mesh = _as_mesh(mesh, device)
    script = _as_script(script)
    return _tear._run_to_files(
        mesh, script._handle, device, _fspath(output, "output"), start_frame, frames or 0,
        "" if report is None else _fspath(report, "report"), up_axis,
        None if meters_per_unit is None else float(meters_per_unit),
        "" if checkpoint is None else _fspath(checkpoint, "checkpoint"), int(checkpoint_every), bool(resume),
        int(writer_threads))


class DeviceArray:
    """A cloth's positions where its backend keeps them (``Cloth.positions``), through the DLPack
    protocol: ``__dlpack__`` and ``__dlpack_device__`` (``(2, gpu)`` for CUDA, ``(1, 0)`` for the
    CPU). Hand it to ``torch.from_dlpack``, ``cupy.from_dlpack`` or ``numpy.from_dlpack``; on the
    CPU ``numpy.asarray`` takes it too. ``shape`` is ``(node_count, 3)``, ``dtype`` ``"float32"``."""

    __slots__ = ("_handle", "shape")
    dtype = "float32"

    def __init__(self, handle):
        self._handle = handle
        self.shape = (handle.node_count, 3)

    def __dlpack__(self, *, stream=None, max_version=None, dl_device=None, copy=None):
        # The cloth's queued work is waited for before the capsule is made, so it is ready on any
        # stream the consumer names.
        if copy:
            raise BufferError("tear: Cloth.positions is handed out without a copy (copy=True asked)")
        return self._handle._positions()

    def __dlpack_device__(self):
        return tuple(self._handle._positions_device())

    def __array__(self, dtype=None, copy=None):
        import numpy
        if self.__dlpack_device__()[0] != 1:
            raise TypeError("tear: the positions are in GPU memory; use cloth.mesh().points for a host copy")
        array = numpy.from_dlpack(self)
        return array if dtype is None else array.astype(dtype, copy=bool(copy))

    def __repr__(self):
        kind, number = self.__dlpack_device__()
        where = "cuda:%d" % number if kind == 2 else "cpu"
        return "<tear.DeviceArray %s float32 on %s>" % (self.shape, where)


class Cloth:
    """A cloth held on a backend, cut and stepped in place.

    ``Cloth(mesh, device="auto", script=None)``: the mesh must be cuttable (``BadInput``
    otherwise); with a ``script`` that has a ``simulation`` block, the cloth simulates it and
    ``step`` moves it.
    """

    __slots__ = ("_handle",)

    def __init__(self, mesh, *, device="auto", script=None):
        mesh = _as_mesh(mesh, device)
        handle = None if script is None else _as_script(script)._handle
        self._handle = _tear._make_cloth(mesh, device, handle)

    node_count = property(lambda self: self._handle.node_count, doc="Nodes now.")
    face_count = property(lambda self: self._handle.face_count, doc="Faces now.")
    device = property(lambda self: self._handle.device, doc='"cpu" or "cuda".')
    simulated = property(lambda self: self._handle.simulated, doc="True when it simulates.")

    def cut(self, polyline, *, space="rest-xy", snap=0.2):
        """Cuts along a 2D polyline (at least two (u, v) points) in ``space``: ``"uv"``,
        ``"rest-xy"``, ``"rest-xz"`` or ``"rest-yz"`` (docs/cut-script.md). Returns the counts
        before and after and the time taken (``ms``)."""
        points = [(float(p[0]), float(p[1])) for p in polyline]
        return self._handle._cut(points, space, float(snap))

    def step(self, frames=1):
        """Advances the simulation ``frames`` frames (1/fps s each). ``UsageError`` without a
        simulation; ``RuntimeFailure`` when it diverges."""
        self._handle._step(int(frames))

    def mesh(self):
        """A copy of the cloth's mesh now, on the host (normals recomputed once it has moved, as
        ``tear run`` writes them)."""
        return self._handle._mesh()

    @property
    def positions(self):
        """The positions where the backend keeps them, without a copy: a ``(node_count, 3)``
        float32 array in GPU memory on ``"cuda"`` (host memory on ``"cpu"``) that
        ``torch.from_dlpack``, ``cupy.from_dlpack`` or ``numpy.from_dlpack`` takes through DLPack
        (a ``DeviceArray``). Read it, do not write it (``set_positions`` does that); it is valid
        until the cloth next changes (``cut``, ``step``, ``set_positions``), which may move the
        buffer."""
        return DeviceArray(self._handle)

    def set_positions(self, points):
        """Replaces the positions (velocities and rest shape stay) with a ``(node_count, 3)``
        array: NumPy or anything that speaks DLPack, float32 and C-contiguous, in host memory or,
        for a cloth on ``"cuda"``, in the same GPU's memory (copied there without a trip through
        the host). Lists and NumPy arrays of other dtypes are converted. ``UsageError`` for a wrong
        shape or device."""
        if not hasattr(points, "__dlpack__") or type(points).__module__ == "numpy":
            import numpy
            points = numpy.ascontiguousarray(points, dtype=numpy.float32)
        self._handle._set_positions(points)

    def __repr__(self):
        return f"<tear.Cloth {self.node_count} nodes, {self.face_count} faces on {self.device}>"
