#!/usr/bin/env python3
"""The Python module `tear` against the `tear` command line.

    test_module.py TEAR_BINARY SOURCE_DIR MODULE_DIR
    test_module.py --missing REASON

Checks that frames from Python, once written, are byte-identical to `tear run`'s for the same
inputs (OBJ, PLY, GLB and per-frame USD layers; a cut-only and a simulated script), and so is a
whole run written by `tear.run(..., output=...)`; the arrays' dtypes, shapes and read-only flags,
and that they view the frame's buffers without a copy; every error class, with the CLI's message;
memory flat over 1,000 frames iterated; a DLPack round trip with NumPy; `tear.Cloth`, and its
positions through DLPack both ways (NumPy; PyTorch and CuPy on a GPU where they are installed,
skipped otherwise); scripts from dicts of many shapes (the examples, nested simulation blocks,
ints as floats, bools, keys that are not strings, deep nesting) against the same scripts read
from files.

Exit 0 when every check holds, 1 when one fails. `--missing` (what CMake runs where the module
could not be built: no nanobind or no Python headers) exits 77, skipped, with REASON, unless
TEAR_REQUIRE_PYTHON=1 (CI), where it fails.
"""

import gc
import os
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest

if len(sys.argv) >= 2 and sys.argv[1] == "--missing":
    reason = " ".join(sys.argv[2:]) or "the Python module was not built"
    if os.environ.get("TEAR_REQUIRE_PYTHON") == "1":
        print("python module: %s, and TEAR_REQUIRE_PYTHON=1" % reason, file=sys.stderr)
        sys.exit(1)
    print("python module: skipped: %s (scripts/install-deps.sh installs nanobind; TEAR_REQUIRE_PYTHON=1 "
          "makes this a failure)" % reason)
    sys.exit(77)

TEAR, SOURCE, MODULE_DIR = sys.argv[1], sys.argv[2], sys.argv[3]
del sys.argv[1:4]
sys.path.insert(0, MODULE_DIR)

import numpy as np  # noqa: E402

import tear  # noqa: E402

MESH = os.path.join(SOURCE, "examples", "meshes", "sheet_low.obj")
CUTS = os.path.join(SOURCE, "examples", "scripts", "crossing_cuts.json")
SIMULATED = {
    "version": 1, "frames": 4,
    "cuts": [{"frame": 2, "space": "rest-xy", "polyline": [[0.2, 0.5], [0.8, 0.5]]}],
    "simulation": {"fps": 24, "substeps": 1, "iterations": 10,
                   "pins": [{"box": {"min": [-1, 0.999, -1], "max": [2, 1.001, 1]}}]},
}
ENV = dict(os.environ, OMP_WAIT_POLICY="passive")
if os.environ.get("TEAR_SANITIZED_PYTHON") == "1":
    # The sanitize build preloads ASan's runtime into this Python (tests/CMakeLists.txt); the CLI
    # carries its own runtime and options.
    for name in ("LD_PRELOAD", "ASAN_OPTIONS", "UBSAN_OPTIONS", "TEAR_SANITIZED_PYTHON"):
        ENV.pop(name, None)


def cli(*args):
    """Runs the CLI; returns (exit code, stderr without the leading 'tear: ')."""
    done = subprocess.run([TEAR] + [str(a) for a in args], capture_output=True, text=True, env=ENV)
    message = done.stderr.strip()
    if message.startswith("tear: "):
        message = message[len("tear: "):]
    return done.returncode, message


def read(path):
    with open(path, "rb") as f:
        return f.read()


def rss_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


class Work(unittest.TestCase):
    def setUp(self):
        self._dir = tempfile.TemporaryDirectory(prefix="tear-python-")
        self.work = self._dir.name

    def tearDown(self):
        self._dir.cleanup()

    def path(self, *parts):
        return os.path.join(self.work, *parts)

    def script_file(self, data, name="shot.json"):
        import json
        path = self.path(name)
        with open(path, "w") as f:
            json.dump(data, f)
        return path


class Identical(Work):
    """Frames from Python, written, are the CLI's bytes."""

    def compare_iterated(self, script_path, extension, start_frame=1):
        code, message = cli("run", MESH, script_path, "-o", self.path("cli", "f.####." + extension),
                            "--device", "cpu", "--start-frame", start_frame)
        self.assertEqual(code, 0, message)
        mesh = tear.read_mesh(MESH, device="cpu")
        script = tear.Script.load(script_path)
        count = 0
        for frame in tear.run(mesh, script, device="cpu", start_frame=start_frame):
            frame.write(self.path("py", "f.####." + extension))
            name = "f.%04d.%s" % (frame.number, extension)
            self.assertEqual(read(self.path("py", name)), read(self.path("cli", name)), name)
            count += 1
        self.assertEqual(count, script.frames)
        self.assertEqual(sorted(os.listdir(self.path("py"))), sorted(os.listdir(self.path("cli"))))

    def test_cuts_every_format(self):
        for extension in ("ply", "obj", "glb", "usda"):
            with self.subTest(extension=extension):
                self.compare_iterated(CUTS, extension)
                self.tearDown()
                self.setUp()

    def test_simulated(self):
        script = self.script_file(SIMULATED)
        for extension in ("ply", "obj"):
            with self.subTest(extension=extension):
                self.compare_iterated(script, extension, start_frame=1001)
                self.tearDown()
                self.setUp()
                script = self.script_file(SIMULATED)

    def test_run_to_files(self):
        script = self.script_file(SIMULATED)
        for output in ("f.####.ply", "shot.usda"):
            with self.subTest(output=output):
                code, message = cli("run", MESH, script, "-o", self.path("cli", output), "--device", "cpu",
                                    "--report", self.path("cli", "report.json"))
                self.assertEqual(code, 0, message)
                summary = tear.run(MESH, script, device="cpu", output=self.path("py", output),
                                   report=self.path("py", "report.json"))
                self.assertEqual(summary["frames"], 4)
                self.assertEqual(sorted(os.listdir(self.path("py"))), sorted(os.listdir(self.path("cli"))))
                for name in os.listdir(self.path("cli")):
                    if name != "report.json":
                        self.assertEqual(read(self.path("py", name)), read(self.path("cli", name)), name)


class Threads(Work):
    def test_gil_released_while_the_library_works(self):
        # Another Python thread counts while a run writes its frames: it only can when the run has
        # let go of the GIL.
        script = self.script_file(dict(SIMULATED, frames=40))
        count = [0]
        done = threading.Event()

        def counter():
            while not done.is_set():
                count[0] += 1

        thread = threading.Thread(target=counter)
        thread.start()
        try:
            time.sleep(0.05)
            before = count[0]
            tear.run(MESH, script, device="cpu", output=self.path("out", "f.####.ply"))
            during = count[0] - before
        finally:
            done.set()
            thread.join()
        self.assertGreater(during, 10000, "the other thread counted %d while the run went on" % during)


class Arrays(Work):
    def test_dtypes_shapes_read_only(self):
        frames = list(tear.run(MESH, CUTS, device="cpu"))
        last = frames[-1]
        n, f = last.node_count, last.face_count
        expected = {
            "points": (np.float32, (n, 3)), "faces": (np.int32, (f, 3)), "uvs": (np.float32, (f, 3, 2)),
            "normals": (np.float32, (f, 3, 3)), "velocities": (np.float32, (n, 3)), "ids": (np.int32, (n,)),
            "origins": (np.int32, (n,)), "origin_weights": (np.float32, (n, 2)),
        }
        for name, (dtype, shape) in expected.items():
            with self.subTest(array=name):
                array = getattr(last, name)
                self.assertIsInstance(array, np.ndarray)
                self.assertEqual(array.dtype, dtype)
                self.assertEqual(array.shape, shape)
                self.assertFalse(array.flags.writeable)
                self.assertFalse(array.flags.owndata)
                self.assertTrue(array.flags.c_contiguous)
                with self.assertRaises(ValueError):
                    array[...] = 0
                # A view of the frame's buffer: the same memory every time, no copy.
                self.assertEqual(array.__array_interface__["data"][0],
                                 getattr(last, name).__array_interface__["data"][0])
        self.assertTrue(np.array_equal(last.ids, np.arange(n, dtype=np.int32)))
        self.assertEqual([frame.number for frame in frames], [1, 2, 3])
        self.assertGreater(last.node_count, frames[0].node_count - 1)
        self.assertGreater(len(last.torn_edges), 0)
        self.assertEqual(last.torn_edges.shape[1], 2)

    def test_view_keeps_frame_alive(self):
        points = next(iter(tear.run(MESH, CUTS, device="cpu"))).points
        copy = points.copy()
        gc.collect()
        _ = [np.zeros(1000) for _ in range(100)]
        self.assertTrue(np.array_equal(points, copy))

    def test_mesh_without_uvs_or_velocities(self):
        path = self.path("tri.obj")
        with open(path, "w") as f:
            f.write("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
        mesh = tear.read_mesh(path)
        self.assertIsNone(mesh.uvs)
        self.assertIsNone(mesh.normals)
        self.assertEqual(mesh.points.shape, (3, 3))

    def test_dlpack_round_trip(self):
        frame = next(iter(tear.run(MESH, CUTS, device="cpu")))
        self.assertEqual(frame.__dlpack_device__(), (1, 0))
        points = np.from_dlpack(frame)
        self.assertEqual(points.dtype, np.float32)
        self.assertEqual(points.shape, (frame.node_count, 3))
        self.assertTrue(np.array_equal(points, frame.points))
        self.assertTrue(np.shares_memory(points, frame.points))
        del frame
        gc.collect()
        self.assertTrue(np.isfinite(points).all())  # the capsule keeps the frame's buffer alive

    @unittest.skipIf(os.environ.get("TEAR_SANITIZED_PYTHON") == "1",
                     "ASan's quarantine keeps freed memory resident (checked by the other builds)")
    def test_memory_flat_over_1000_frames(self):
        script = tear.Script({"version": 1, "frames": 1000,
                              "cuts": [{"frame": 1, "space": "rest-xy", "polyline": [[0.2, 0.5], [0.8, 0.5]]}]})
        mesh = tear.read_mesh(MESH, device="cpu")
        frames = tear.run(mesh, script, device="cpu")
        self.assertEqual(len(frames), 1000)
        total = 0.0
        before = None
        for frame in frames:
            total += float(frame.points[0, 0]) + float(frame.faces.shape[0])
            if frame.number == 100:
                gc.collect()
                before = rss_bytes()
        gc.collect()
        growth = rss_bytes() - before
        self.assertLess(growth, 8 << 20, "resident memory grew by %d bytes over 900 frames" % growth)
        self.assertEqual(len(frames), 0)


class Errors(Work):
    def assert_same(self, error_class, exit_code, call, *cli_args):
        code, message = cli(*cli_args)
        self.assertEqual(code, exit_code, message)
        with self.assertRaises(error_class) as caught:
            call()
        self.assertEqual(str(caught.exception), message)
        self.assertEqual(caught.exception.exit_code, exit_code)
        self.assertIsInstance(caught.exception, tear.Error)

    def test_usage_error(self):
        self.assert_same(tear.UsageError, 1, lambda: tear.run(MESH, CUTS, device="cpu", output=self.path("f.####.xyz")),
                         "run", MESH, CUTS, "-o", self.path("f.####.xyz"), "--device", "cpu")
        self.assertTrue(issubclass(tear.UsageError, ValueError))

    def test_bad_input_mesh(self):
        missing = self.path("missing.obj")
        self.assert_same(tear.BadInput, 2, lambda: tear.read_mesh(missing),
                         "run", missing, CUTS, "-o", self.path("f.####.obj"), "--device", "cpu")

    def test_bad_input_script(self):
        data = {"version": 1, "frames": 2, "cuts": [{"frame": 3, "space": "rest-xy", "polyline": [[0, 0], [1, 1]]}]}
        path = self.script_file(data)
        self.assert_same(tear.BadInput, 2, lambda: tear.Script(data, name=path),
                         "run", MESH, path, "-o", self.path("f.####.obj"), "--device", "cpu")
        self.assert_same(tear.BadInput, 2, lambda: tear.Script.load(path),
                         "validate", path)

    def test_bad_input_output_is_input(self):
        # The first frame's file would be the mesh itself.
        copy = self.path("cloth.obj")
        with open(copy, "wb") as f:
            f.write(read(MESH))
        one = self.script_file({"version": 1, "frames": 1, "cuts": []})
        self.assert_same(tear.BadInput, 2, lambda: tear.run(copy, one, device="cpu", output=copy),
                         "run", copy, one, "-o", copy, "--device", "cpu")

    def test_runtime_failure(self):
        blocker = self.path("a_file")
        open(blocker, "w").close()
        output = os.path.join(blocker, "out", "f.####.ply")
        self.assert_same(tear.RuntimeFailure, 3, lambda: tear.run(MESH, CUTS, device="cpu", output=output),
                         "run", MESH, CUTS, "-o", output, "--device", "cpu")

    def test_interrupted(self):
        script = self.script_file(dict(SIMULATED, frames=2000, cuts=[]))
        output = self.path("out", "f.####.ply")
        first = self.path("out", "f.0001.ply")

        finished = threading.Event()

        def stop_after_first_frame():
            while not os.path.exists(first):
                if finished.wait(0.01):
                    return  # the run ended without a frame: the assertion below says how
            os.kill(os.getpid(), signal.SIGTERM)

        previous = signal.getsignal(signal.SIGTERM)
        thread = threading.Thread(target=stop_after_first_frame)
        thread.start()
        try:
            with self.assertRaises(tear.Interrupted) as caught:
                tear.run(MESH, script, device="cpu", output=output, checkpoint=self.path("shot.ckpt"))
        finally:
            finished.set()
            thread.join()
        self.assertEqual(signal.getsignal(signal.SIGTERM), previous)  # the handler is given back
        # Stopped between frames, or inside one (its part done dropped, as the CLI says).
        self.assertRegex(str(caught.exception),
                         r"^stopped after frame \d+ of 2000(, inside frame \d+ \(dropped: it is computed again on "
                         r"resume\))?; '--resume' goes on from ")
        self.assertEqual(caught.exception.exit_code, 4)


class ScriptsFromDicts(Work):
    """`tear.Script(dict)` on dicts of every shape a caller may build: the same script as the file,
    or `BadInput` with the CLI's message; never a crash of the interpreter."""

    def examples(self):
        import glob
        import json
        paths = sorted(glob.glob(os.path.join(SOURCE, "examples", "**", "*.json"), recursive=True))
        self.assertTrue(paths)
        for path in paths:
            with open(path) as f:
                yield path, json.load(f)

    def assert_same_script(self, a, b):
        for name in ("frames", "snap", "version", "cut_count", "simulated", "fps"):
            self.assertEqual(getattr(a, name), getattr(b, name), name)

    def test_examples_as_dicts(self):
        for path, data in self.examples():
            with self.subTest(path=os.path.relpath(path, SOURCE)):
                try:
                    loaded = tear.Script.load(path)
                except tear.BadInput as e:  # a JSON file of examples/ that is not a script
                    with self.assertRaisesRegex(tear.BadInput, "^" + re.escape(str(e)) + "$"):
                        tear.Script(data, name=path)
                    continue
                self.assert_same_script(tear.Script(data, name=path), loaded)

    def test_simulation_blocks(self):
        nested = dict(SIMULATED, simulation=dict(SIMULATED["simulation"], gravity=[0, -9.81, 0],
                                                 tearing={"stretch": 1.5, "weave": {"warp": [1, 0], "weft_strength": 2}}))
        path = self.script_file(nested)
        self.assert_same_script(tear.Script(nested), tear.Script.load(path))
        self.assertTrue(tear.Script(nested).simulated)
        self.assertEqual(tear.Script(dict(SIMULATED, simulation={"fps": 30})).fps, 30)

    def test_numbers_and_empty_lists(self):
        as_floats = tear.Script({"version": 1.0, "frames": 4.0, "snap": 0, "cuts": []})
        self.assertEqual((as_floats.frames, as_floats.cut_count, as_floats.snap), (4, 0, 0.0))
        self.assertTrue(tear.Script({"version": 1, "frames": 1, "cuts": [], "simulation": {"pins": []}}).simulated)
        with self.assertRaisesRegex(tear.BadInput, r"^script: frames: expected an integer in 1\.\.\d+, got 4\.5$"):
            tear.Script({"version": 1, "frames": 4.5})
        with self.assertRaisesRegex(tear.BadInput, r"^script: frames: expected an integer in 1\.\.\d+, got "):
            tear.Script({"version": 1, "frames": 2 ** 64})

    def test_bools_are_not_numbers(self):
        # Python's bools are ints; JSON's are not, and neither are a script's.
        with self.assertRaisesRegex(tear.BadInput, r"^script: version: expected 1, got true$"):
            tear.Script({"version": True, "frames": 2})
        with self.assertRaisesRegex(tear.BadInput, r"^script: frames: .*, got true$"):
            tear.Script({"version": 1, "frames": True})
        with self.assertRaisesRegex(tear.BadInput, r"^script: snap: expected a number, got false$"):
            tear.Script({"version": 1, "frames": 2, "snap": False})

    def test_keys_that_are_not_strings(self):
        with self.assertRaisesRegex(tear.BadInput, r'^script: \["1"\]: unknown key '):
            tear.Script({"version": 1, "frames": 2, 1: 2})
        with self.assertRaisesRegex(tear.BadInput, r'^script: \["\\u0000"\]: unknown key '):
            tear.Script({"version": 1, "frames": 2, "\0": 2})
        with self.assertRaises(TypeError):
            tear.Script({"version": 1, "frames": 2, (1, 2): 3})

    def test_deep_nesting(self):
        for depth in (33, 500, 100000):
            deep = []
            for _ in range(depth):
                deep = [deep]
            with self.subTest(depth=depth):
                with self.assertRaises((tear.BadInput, RecursionError)):
                    tear.Script({"version": 1, "frames": 2, "cuts": deep})
        text = '{"version": 1, "frames": 2, "cuts": ' + "[" * 100000 + "]" * 100000 + "}"
        with self.assertRaisesRegex(tear.BadInput, r"^script: the cut script nests arrays and objects deeper than"):
            tear.Script(text)

    def test_not_an_object(self):
        for data in (None, [], 2, "", "[]"):
            with self.subTest(data=data):
                with self.assertRaises(tear.BadInput):
                    tear.Script(data)


class Library(unittest.TestCase):
    def test_refuses_a_library_of_other_headers(self):
        # A libtear.so built from other headers than the module (an older build's, found first
        # through LD_LIBRARY_PATH) corrupted memory at the first script handed across; the module
        # refuses it on import instead. tear_wrong_layout, preloaded, plays that library's part.
        stub = os.environ.get("TEAR_WRONG_LAYOUT_LIBRARY")
        if not stub:
            self.skipTest("TEAR_WRONG_LAYOUT_LIBRARY is not set (ctest sets it)")
        env = dict(os.environ, LD_PRELOAD=(os.environ.get("LD_PRELOAD", "") + " " + stub).strip())
        code = "import sys; sys.path.insert(0, %r); import tear" % MODULE_DIR
        done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
        self.assertEqual(done.returncode, 1, done.stderr)
        self.assertRegex(done.stderr, r"ImportError: tear: \S*libtear\.so was built from other headers than this "
                                      r"module; rebuild both together, or check that LD_LIBRARY_PATH")
        done = subprocess.run([sys.executable, "-c", code + "; tear.Script({'version': 1, 'frames': 1})"],
                              capture_output=True, text=True)
        self.assertEqual(done.returncode, 0, done.stderr)


class ClothApi(Work):
    def test_cut_step_mesh(self):
        cloth = tear.Cloth(MESH, device="cpu", script=SIMULATED)
        before = cloth.node_count
        result = cloth.cut([(0.2, 0.5), (0.8, 0.5)], space="rest-xy")
        self.assertEqual(result["nodes_before"], before)
        self.assertGreater(result["nodes_after"], before)
        self.assertEqual(cloth.node_count, result["nodes_after"])
        rest = cloth.mesh().points.copy()
        cloth.step(frames=2)
        moved = cloth.mesh()
        self.assertEqual(moved.points.shape, rest.shape)
        self.assertFalse(np.array_equal(moved.points, rest))
        moved.write(self.path("moved.ply"))
        self.assertEqual(tear.read_mesh(self.path("moved.ply")).node_count, moved.node_count)

    def test_positions_round_trip_on_the_cpu(self):
        cloth = tear.Cloth(MESH, device="cpu", script=SIMULATED)
        cloth.step(frames=2)
        positions = cloth.positions
        self.assertEqual(positions.__dlpack_device__(), (1, 0))
        points = np.from_dlpack(positions)
        self.assertEqual(points.dtype, np.float32)
        self.assertEqual(points.shape, (cloth.node_count, 3))
        self.assertTrue(np.array_equal(points, cloth.mesh().points))
        self.assertTrue(np.shares_memory(points, np.from_dlpack(cloth.positions)))  # the same buffer, no copy
        # Back in, moved: the mesh shows them; NumPy float64 and lists are converted.
        moved = points.astype(np.float64) + [0.0, 0.0, 0.25]
        cloth.set_positions(moved)
        self.assertTrue(np.array_equal(cloth.mesh().points, moved.astype(np.float32)))
        cloth.set_positions(moved.tolist())
        self.assertTrue(np.array_equal(cloth.mesh().points, moved.astype(np.float32)))
        with self.assertRaisesRegex(tear.UsageError, r"^points: expected shape \(%d, 3\), got \(2, 3\)$"
                                    % cloth.node_count):
            cloth.set_positions(np.zeros((2, 3), np.float32))
        cloth.step()  # stepped on from the positions given
        self.assertTrue(np.isfinite(cloth.mesh().points).all())

    def test_positions_round_trip_on_the_gpu(self):
        """PyTorch and CuPy read the positions in GPU memory without a copy, and hand them back."""
        if not tear.cuda_available():
            self.skipTest("no usable GPU")
        peers = []
        try:
            import torch
            if torch.cuda.is_available():
                peers.append(("torch", lambda a: torch.from_dlpack(a), lambda t: t.data_ptr(),
                              lambda t: t.cpu().numpy()))
        except ImportError:
            pass
        try:
            import cupy
            peers.append(("cupy", lambda a: cupy.from_dlpack(a), lambda t: t.data.ptr, lambda t: cupy.asnumpy(t)))
        except ImportError:
            pass
        if not peers:
            self.skipTest("neither PyTorch with CUDA nor CuPy is installed")
        for name, take, address, to_host in peers:
            with self.subTest(peer=name):
                cloth = tear.Cloth(MESH, device="cuda", script=SIMULATED)
                cloth.step(frames=2)
                self.assertEqual(cloth.positions.__dlpack_device__()[0], 2)  # kDLCUDA
                on_gpu = take(cloth.positions)
                self.assertEqual(address(on_gpu), address(take(cloth.positions)))  # no copy
                self.assertTrue(np.array_equal(to_host(on_gpu), cloth.mesh().points))
                moved = on_gpu * 2 + 1  # a new array on the GPU
                expected = to_host(moved)
                cloth.set_positions(moved)
                self.assertTrue(np.array_equal(cloth.mesh().points, expected))
                cloth.set_positions(expected)  # from the host too
                self.assertTrue(np.array_equal(to_host(take(cloth.positions)), expected))
                print("positions round trip on the GPU with %s" % name)

    def test_step_without_simulation(self):
        cloth = tear.Cloth(tear.read_mesh(MESH), device="cpu")
        with self.assertRaises(tear.UsageError):
            cloth.step()
        with self.assertRaises(tear.UsageError):
            cloth.cut([(0, 0), (1, 1)], space="sideways")

    def test_version(self):
        out = subprocess.run([TEAR, "--version"], capture_output=True, text=True).stdout.strip()
        self.assertEqual("tear " + tear.__version__, out)


if __name__ == "__main__":
    unittest.main(verbosity=2)
