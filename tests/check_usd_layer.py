#!/usr/bin/env python3
"""Reads tear's USD layers back with USD itself (usd-core's `pxr`) and checks them against the PLY
and OBJ frames of the same run.

    check_usd_layer.py TEAR_BINARY SOURCE_DIR

Runs the paper's low-resolution sheet through two crossing cuts and a third one later, with a
simulation block, once into one layer (`shot.usda`), once into PLY frames and once into OBJ frames,
all with `--start-frame 1001`, then checks every time sample of the layer:

- the stage: default prim /cloth, a UsdGeom.Mesh; start/end time codes 1001 and the last frame;
  timeCodesPerSecond and framesPerSecond the simulation's fps; upAxis Y; metersPerUnit 1;
- each sample: UsdGeom.Mesh.ValidateTopology; as many velocities and accelerations as points; `st`
  and `normals` indexed faceVarying primvars and `tear_edge` faceVarying, one value per corner once
  flattened; `extent` the points' box; `rest` (vertex) the input's positions for its nodes; `id`
  (vertex) 0..N-1; `piece` (uniform) one per face, the PLY's face `piece`; accelerations
  (v_f - v_{f-1}) * fps;
- what moves (points, velocities, accelerations, extent, normals) is sampled at every frame, the
  topology and the primvars' indices only at the frames where they change (the cuts' frames);
- points and faces equal the OBJ frame's `v` and `f` lines (node i is `v` i + 1), and the PLY
  frame's vertices and faces (a PLY vertex is a node with one UV and normal: each must agree with
  the points, normals and UVs of the corners that use it); velocities equal the PLY's `vx vy vz`
  when the PLY has them, and always the velocity the solver's implicit Euler step gives,
  (x_f - x_{f-1}) * fps (one substep, no damping);
- `tear_edge` marks boundary edges only, none before the first cut and some after it, and never an
  edge of the cloth's own border;
- file names number from 1001; per-frame layers (`shot.####.usda`) hold their frame; without a
  simulation block the layer has 24 fps; `--up-axis Z --meters-per-unit 0.01` and a `.usd`
  extension;
- UsdValidation: every validator USD registers (core, UsdGeom, UsdShade, UsdSkel, UsdPhysics,
  UsdLux, UsdMedia, UsdUtils; 30 in usd-core 26.11) reports no error or warning on each of these
  layers, nor on the layer of the paper's demo scene (`tear demo -o demo.usda`, 48 frames); on a
  bare stage it must report the missing metadata, so that a run that loaded no validator fails.

Exit 0 when every check holds, 1 when one fails, 77 (skipped, for ctest) when `pxr` (with
UsdValidation) cannot be imported, unless TEAR_REQUIRE_USD=1 (CI), where that is a failure. `pxr`
comes from .venv/ (scripts/install-deps.sh installs usd-core there); the script re-runs itself with
SOURCE_DIR/.venv/bin/python when the Python it was started with lacks it.
"""

import os
import struct
import subprocess
import sys
import tempfile

TEAR, SOURCE = sys.argv[1], sys.argv[2]


def import_pxr():
    try:
        from pxr import Usd, UsdGeom, UsdValidation  # noqa: F401
        return
    except ImportError as error:
        reason = str(error)
    venv_python = os.path.join(SOURCE, ".venv", "bin", "python")
    if os.path.exists(venv_python) and not os.environ.get("TEAR_USD_CHECK_REEXEC"):
        os.environ["TEAR_USD_CHECK_REEXEC"] = "1"
        os.execv(venv_python, [venv_python] + sys.argv)
    message = ("usd-core (pxr, with UsdValidation) is not importable by %s nor by %s (%s); "
               "scripts/install-deps.sh installs it"
               % (sys.executable, venv_python, reason))
    if os.environ.get("TEAR_REQUIRE_USD") == "1":
        print("FAIL: " + message + " (TEAR_REQUIRE_USD=1: it must be there)")
        sys.exit(1)
    print("SKIP: " + message)
    sys.exit(77)


import_pxr()
from pxr import Gf, Sdf, Usd, UsdGeom, UsdValidation  # noqa: E402

FRAMES = 6
FPS = 30
START = 1001
FIRST_CUT = 3
SCRIPT = """{ "version": 1, "frames": %d,
  "cuts": [ { "frame": %d, "space": "rest-xy", "polyline": [[0.2, 0.25], [0.8, 0.75]] },
            { "frame": %d, "space": "rest-xy", "polyline": [[0.2, 0.75], [0.8, 0.25]] },
            { "frame": 5, "space": "uv", "polyline": [[0.1, 0.4], [0.9, 0.4]] } ],
  "simulation": { "fps": %d, "substeps": 1, "iterations": 10, "damping": 0,
                  "pins": [ { "box": { "min": [-1, 0.999, -1], "max": [2, 1.001, 1] } } ] } }
""" % (FRAMES, FIRST_CUT, FIRST_CUT, FPS)

failures = []
checks = 0


def check(condition, what):
    global checks
    checks += 1
    if not condition:
        failures.append(what)
        if len(failures) <= 20:
            print("FAIL: " + what)


def f32(x):
    return struct.unpack("<f", struct.pack("<f", float(x)))[0]


def tear(*args):
    command = [TEAR] + list(args) + ["--device", "cpu"]
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        print("FAIL: %s exited %d: %s" % (" ".join(command), result.returncode, result.stderr.strip()))
        sys.exit(1)
    return result.stdout


def read_obj(path):
    points, faces = [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                points.append(tuple(f32(x) for x in parts[1:4]))
            elif parts[0] == "f":
                faces.append([int(corner.split("/")[0]) - 1 for corner in parts[1:]])
    return points, faces


PLY_TYPES = {"char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h", "ushort": "H",
             "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I", "float": "f", "float32": "f",
             "double": "d", "float64": "d"}


def read_ply(path):
    """{element: [ {property: value or list} ]} of a binary little-endian PLY."""
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    elements = []
    for line in data[:end].decode("ascii").splitlines():
        parts = line.split()
        if parts[0] == "format":
            assert parts[1] == "binary_little_endian", parts
        elif parts[0] == "element":
            elements.append((parts[1], int(parts[2]), []))
        elif parts[0] == "property":
            if parts[1] == "list":
                elements[-1][2].append((parts[4], PLY_TYPES[parts[2]], PLY_TYPES[parts[3]]))
            else:
                elements[-1][2].append((parts[2], PLY_TYPES[parts[1]], None))
    out, at = {}, end
    for name, count, properties in elements:
        rows = []
        for _ in range(count):
            row = {}
            for prop, kind, item in properties:
                if item is None:
                    (row[prop],) = struct.unpack_from("<" + kind, data, at)
                    at += struct.calcsize(kind)
                else:
                    (n,) = struct.unpack_from("<" + kind, data, at)
                    at += struct.calcsize(kind)
                    row[prop] = list(struct.unpack_from("<%d%s" % (n, item), data, at))
                    at += n * struct.calcsize(item)
            rows.append(row)
        out[name] = rows
    return out


def where_of(frame):
    return "frame %d: " % frame


def edge_faces(indices):
    """{(a, b) unordered: number of faces using the edge}."""
    count = {}
    for f in range(len(indices) // 3):
        for k in range(3):
            a, b = indices[3 * f + k], indices[3 * f + (k + 1) % 3]
            key = (min(a, b), max(a, b))
            count[key] = count.get(key, 0) + 1
    return count


VALIDATION = {"validators": 0, "stages": 0}


def validate(stage, what):
    """Runs every validator USD registers (UsdValidationRegistry: the core, UsdGeom, UsdShade,
    UsdSkel, UsdPhysics, UsdLux, UsdMedia and UsdUtils ones) over the stage at all its time codes;
    each error or warning they report fails the check."""
    registry = UsdValidation.ValidationRegistry()
    validators = registry.GetOrLoadAllValidators()
    VALIDATION["validators"] = len(validators)
    VALIDATION["stages"] += 1
    context = UsdValidation.ValidationContext(validators)
    reports = [e for e in context.Validate(stage, UsdValidation.ValidationTimeRange())
               if e.GetType() in (UsdValidation.ValidationErrorType.Error, UsdValidation.ValidationErrorType.Warn)]
    for e in reports[:10]:
        print("%s: UsdValidation %s %s: %s" % (what, e.GetType(), e.GetName(), e.GetMessage()))
    check(not reports, "%s: UsdValidation reports %d errors and warnings" % (what, len(reports)))


def main():
    mesh = os.path.join(SOURCE, "examples", "meshes", "sheet_low.obj")
    work = tempfile.mkdtemp(prefix="tear_usd_check.")
    script = os.path.join(work, "shot.json")
    with open(script, "w") as f:
        f.write(SCRIPT)
    layer_path = os.path.join(work, "usd", "shot.usda")
    tear("run", mesh, script, "-o", layer_path, "--start-frame", str(START))
    tear("run", mesh, script, "-o", os.path.join(work, "ply", "shot.####.ply"), "--start-frame", str(START))
    verbose = tear("run", mesh, script, "-o", os.path.join(work, "obj", "shot.####.obj"), "--start-frame", str(START),
                   "-v")
    last = START + FRAMES - 1
    numbers = list(range(START, last + 1))
    check(sorted(os.listdir(os.path.join(work, "usd"))) == ["shot.usda"], "the layer alone, no temporaries left")
    check(sorted(os.listdir(os.path.join(work, "ply"))) == ["shot.%04d.ply" % n for n in numbers],
          "PLY files numbered from %d: %s" % (START, sorted(os.listdir(os.path.join(work, "ply")))))
    check(verbose.splitlines()[0].startswith("frame %d/%d: " % (START, last)), "-v line: " + verbose.splitlines()[0])

    stage = Usd.Stage.Open(layer_path)
    check(stage is not None, "the layer opens")
    validate(stage, layer_path)
    check(stage.GetStartTimeCode() == START and stage.GetEndTimeCode() == last,
          "time codes %s..%s" % (stage.GetStartTimeCode(), stage.GetEndTimeCode()))
    check(stage.GetTimeCodesPerSecond() == FPS and stage.GetFramesPerSecond() == FPS,
          "fps %s/%s" % (stage.GetTimeCodesPerSecond(), stage.GetFramesPerSecond()))
    check(UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.y, "upAxis Y")
    check(UsdGeom.GetStageMetersPerUnit(stage) == 1.0, "metersPerUnit 1")
    prim = stage.GetDefaultPrim()
    check(prim.GetPath() == Sdf.Path("/cloth") and prim.IsA(UsdGeom.Mesh), "default prim /cloth, a Mesh")
    geom = UsdGeom.Mesh(prim)
    primvars = UsdGeom.PrimvarsAPI(prim)
    st, tear_edge = primvars.GetPrimvar("st"), primvars.GetPrimvar("tear_edge")
    normal_primvar, rest, ids, piece = (primvars.GetPrimvar("normals"), primvars.GetPrimvar("rest"),
                                        primvars.GetPrimvar("id"), primvars.GetPrimvar("piece"))
    check(st.GetInterpolation() == UsdGeom.Tokens.faceVarying and st.IsIndexed(), "st indexed faceVarying")
    check(tear_edge.GetInterpolation() == UsdGeom.Tokens.faceVarying, "tear_edge faceVarying")
    check(normal_primvar.GetInterpolation() == UsdGeom.Tokens.faceVarying and normal_primvar.IsIndexed(),
          "normals an indexed faceVarying primvar")
    check(rest.GetInterpolation() == UsdGeom.Tokens.vertex and rest.GetTypeName() == Sdf.ValueTypeNames.Point3fArray,
          "rest a vertex point3f primvar")
    check(ids.GetInterpolation() == UsdGeom.Tokens.vertex and ids.GetTypeName() == Sdf.ValueTypeNames.IntArray,
          "id a vertex int primvar")
    check(piece.GetInterpolation() == UsdGeom.Tokens.uniform and piece.GetTypeName() == Sdf.ValueTypeNames.IntArray,
          "piece a uniform int primvar")
    accelerations = geom.GetPrim().GetAttribute("accelerations")
    check(accelerations.IsValid() and accelerations.GetTypeName() == Sdf.ValueTypeNames.Vector3fArray,
          "accelerations a vector3f[]")
    for attribute in (geom.GetPointsAttr(), geom.GetVelocitiesAttr(), accelerations, geom.GetExtentAttr(),
                      normal_primvar.GetAttr()):
        check(attribute.GetTimeSamples() == [float(n) for n in numbers],
              "%s sampled at every frame: %s" % (attribute.GetName(), attribute.GetTimeSamples()))
    # The cuts' frames (and the first): where the topology and the indices change.
    changes = [float(START), float(START + FIRST_CUT - 1), float(START + 4)]
    for attribute in (geom.GetFaceVertexIndicesAttr(), geom.GetFaceVertexCountsAttr(), st.GetIndicesAttr(),
                      tear_edge.GetAttr(), piece.GetAttr(), ids.GetAttr()):
        check(attribute.GetTimeSamples() == changes,
              "%s sampled where it changes %s: %s" % (attribute.GetName(), changes, attribute.GetTimeSamples()))
    # A normal's indices change with the topology, and where a node's corners stop or start sharing
    # one normal (a face of no area).
    normal_indices = normal_primvar.GetIndicesAttr().GetTimeSamples()
    check(set(changes) <= set(normal_indices) and len(normal_indices) < len(numbers),
          "normals:indices sampled where they change: %s" % normal_indices)
    input_points, _ = read_obj(mesh)

    previous_points = None
    previous_velocities = None
    input_border = None
    ply_has_velocities = None
    for i, frame in enumerate(numbers):
        points = [tuple(p) for p in geom.GetPointsAttr().Get(frame)]
        indices = list(geom.GetFaceVertexIndicesAttr().Get(frame))
        counts = list(geom.GetFaceVertexCountsAttr().Get(frame))
        velocities = [tuple(v) for v in geom.GetVelocitiesAttr().Get(frame)]
        normals = [tuple(n) for n in normal_primvar.ComputeFlattened(frame)]
        uvs = [tuple(t) for t in st.ComputeFlattened(frame)]
        rests = [tuple(p) for p in rest.Get(frame)]
        check(len(rests) == len(points) and rests[:len(input_points)] == input_points,
              where_of(frame) + "rest: the input's positions for its nodes")
        check(list(ids.Get(frame)) == list(range(len(points))), where_of(frame) + "id 0..N-1")
        frame_accelerations = [tuple(a) for a in accelerations.Get(frame)]
        check(len(frame_accelerations) == len(points), where_of(frame) + "one acceleration per point")
        pieces = list(piece.Get(frame))
        marks = list(tear_edge.Get(frame))
        where = "frame %d: " % frame
        valid, why = UsdGeom.Mesh.ValidateTopology(indices, counts, len(points))
        check(valid, where + "ValidateTopology: " + why)
        check(set(counts) == {3}, where + "triangles")
        check(len(velocities) == len(points), where + "%d velocities, %d points" % (len(velocities), len(points)))
        check(len(uvs) == len(indices) and len(normals) == len(indices) and len(marks) == len(indices),
              where + "one st, normal and tear_edge per corner (%d, %d, %d for %d corners)"
              % (len(uvs), len(normals), len(marks), len(indices)))
        extent = [tuple(e) for e in geom.GetExtentAttr().Get(frame)]
        box = [tuple(min(p[k] for p in points) for k in range(3)), tuple(max(p[k] for p in points) for k in range(3))]
        check(extent == box, where + "extent %s, points' box %s" % (extent, box))

        # The OBJ frame: node i is v line i + 1.
        obj_points, obj_faces = read_obj(os.path.join(work, "obj", "shot.%04d.obj" % frame))
        check(obj_points == points, where + "points equal the OBJ's v lines")
        check([n for face in obj_faces for n in face] == indices, where + "faces equal the OBJ's f lines")

        # The PLY frame: each vertex is one node with one UV and normal.
        ply = read_ply(os.path.join(work, "ply", "shot.%04d.ply" % frame))
        vertices, faces = ply["vertex"], ply["face"]
        check(len(faces) == len(counts), where + "%d PLY faces, %d USD faces" % (len(faces), len(counts)))
        vertex_node = {}
        ply_ok = True
        for f, face in enumerate(faces[:len(counts)]):
            corners = face["vertex_indices"]
            for k in range(3):
                c, vertex = 3 * f + k, vertices[corners[k]]
                node = indices[c]
                ply_ok &= vertex_node.setdefault(corners[k], node) == node
                ply_ok &= (vertex["x"], vertex["y"], vertex["z"]) == points[node]
                ply_ok &= (vertex["nx"], vertex["ny"], vertex["nz"]) == normals[c]
                ply_ok &= (vertex["s"], vertex["t"]) == uvs[c]
                if "id" in vertex:
                    ply_ok &= vertex["id"] == node
                if "vx" in vertex:
                    ply_ok &= (vertex["vx"], vertex["vy"], vertex["vz"]) == velocities[node]
        check(ply_ok, where + "the PLY's vertices (positions, normals, UVs, ids, velocities) equal the layer's")
        check([face["piece"] for face in faces] == pieces, where + "piece equals the PLY's face piece")
        check(len(set(vertex_node.values())) == len(points), where + "every point is a PLY vertex")
        ply_has_velocities = "vx" in vertices[0]

        # The solver's step: v = (x - x_before) / h, h = 1/fps, for the nodes of the frame before
        # (a cut appends nodes and keeps the old ones where they were).
        if previous_points is not None:
            worst = 0.0
            for n, before in enumerate(previous_points):
                for k in range(3):
                    worst = max(worst, abs(velocities[n][k] - (points[n][k] - before[k]) * FPS))
            check(worst < 1e-4, where + "velocities are the step's (x - x_before) * fps, worst error %g" % worst)
            check(any(v != (0, 0, 0) for v in velocities), where + "the cloth moves")
            worst = 0.0
            for n, before in enumerate(previous_velocities):
                for k in range(3):
                    want = f32((velocities[n][k] - before[k]) * FPS)
                    worst = max(worst, abs(frame_accelerations[n][k] - want) / max(1.0, abs(want)))
            check(worst < 1e-5, where + "accelerations are (v - v_before) * fps, worst error %g" % worst)
        else:
            check(all(a == (0, 0, 0) for a in frame_accelerations), where + "no acceleration at the first frame")
        previous_velocities = velocities

        # tear_edge: boundary edges made by the cuts only.
        edges = edge_faces(indices)
        border = {e for e, n in edges.items() if n == 1}
        if input_border is None:
            input_border = border
        marked = set()
        check(set(marks) <= {0, 1}, where + "tear_edge is 0 or 1")
        for c, mark in enumerate(marks):
            if mark:
                a, b = indices[c], indices[c - c % 3 + (c % 3 + 1) % 3]
                marked.add((min(a, b), max(a, b)))
        check(marked <= border, where + "%d marked edges are not boundary edges" % len(marked - border))
        check(not (marked & input_border), where + "an edge of the cloth's own border is marked")
        if START + FIRST_CUT - 1 > frame:
            check(not marked, where + "tear_edge marks %d edges before the first cut" % len(marked))
        else:
            check(len(marked) > 0, where + "tear_edge marks no edge after a cut")
        previous_points = points

    # Per-frame layers, a run without simulation, the metadata flags, a .usd extension.
    tear("run", mesh, script, "-o", os.path.join(work, "frames", "shot.####.usda"), "--start-frame", str(START),
         "--frames", "2")
    for frame in (START, START + 1):
        one = Usd.Stage.Open(os.path.join(work, "frames", "shot.%04d.usda" % frame))
        validate(one, "per-frame layer %d" % frame)
        check(one.GetStartTimeCode() == frame == one.GetEndTimeCode(), "per-frame layer %d's time codes" % frame)
        check(UsdGeom.Mesh(one.GetPrimAtPath("/cloth")).GetPointsAttr().GetTimeSamples() == [frame],
              "per-frame layer %d's sample" % frame)
        check(UsdGeom.Mesh(one.GetPrimAtPath("/cloth")).GetPointsAttr().Get(frame) == geom.GetPointsAttr().Get(frame),
              "per-frame layer %d's points equal the sequence's" % frame)
    still = os.path.join(work, "still.json")
    with open(still, "w") as f:
        f.write('{ "version": 1, "frames": 3, "cuts": [ { "frame": 2, "space": "rest-xy", '
                '"polyline": [[0.1, 0.5], [0.9, 0.5]] } ] }')
    usd_path = os.path.join(work, "still.usd")
    tear("run", mesh, still, "-o", usd_path, "--up-axis", "Z", "--meters-per-unit", "0.01")
    still_stage = Usd.Stage.Open(usd_path)
    check(still_stage.GetTimeCodesPerSecond() == 24 and still_stage.GetFramesPerSecond() == 24,
          "24 fps without a simulation block")
    check(still_stage.GetStartTimeCode() == 1 and still_stage.GetEndTimeCode() == 3, "time codes 1..3 by default")
    check(UsdGeom.GetStageUpAxis(still_stage) == UsdGeom.Tokens.z, "--up-axis Z")
    check(UsdGeom.GetStageMetersPerUnit(still_stage) == 0.01, "--meters-per-unit 0.01")
    still_geom = UsdGeom.Mesh(still_stage.GetDefaultPrim())
    check(all(v == (0, 0, 0) for v in still_geom.GetVelocitiesAttr().Get(3)), "no simulation: velocities 0")
    check(list(UsdGeom.PrimvarsAPI(still_geom).GetPrimvar("tear_edge").Get(1)).count(1) == 0
          and list(UsdGeom.PrimvarsAPI(still_geom).GetPrimvar("tear_edge").Get(2)).count(1) > 0,
          "tear_edge before and after the cut without simulation")

    validate(still_stage, usd_path)

    # The validators run: a stage without the metadata they ask for is reported.
    bare = Usd.Stage.CreateInMemory()
    UsdGeom.Mesh.Define(bare, "/cloth")
    bare_reports = {e.GetName() for e in UsdValidation.ValidationContext(
        UsdValidation.ValidationRegistry().GetOrLoadAllValidators()).Validate(bare)}
    check({"MissingDefaultPrim", "MissingUpAxisMetadata", "MissingMetersPerUnitMetadata"} <= bare_reports,
          "UsdValidation reports %s on a stage without metadata" % sorted(bare_reports))

    # The layer of the paper's demo scene (tear demo: 48 frames, six cuts, simulated).
    demo_path = os.path.join(work, "demo", "demo.usda")
    tear("demo", "-o", demo_path)
    demo_stage = Usd.Stage.Open(demo_path)
    check(demo_stage.GetEndTimeCode() - demo_stage.GetStartTimeCode() == 47, "the demo's layer holds 48 frames")
    validate(demo_stage, demo_path)

    print("check_usd_layer: usd-core %s, %d frames of %s, %d checks, %d failed%s; UsdValidation: %d validators "
          "over %d stages (the demo's %s among them)"
          % (".".join(map(str, Usd.GetVersion())), FRAMES, layer_path, checks, len(failures),
             "" if ply_has_velocities else " (this PLY writer has no vx vy vz: velocities checked against the step)",
             VALIDATION["validators"], VALIDATION["stages"], demo_path))
    if failures:
        sys.exit(1)
    import shutil
    shutil.rmtree(work)


main()
