// tear: the whole public API in one header. `find_package(tear)` and `tear::tear` bring it in;
// examples/consumer shows a program built against an installed tree.
#pragma once

#include "tear/bench.h"
#include "tear/cloth.h"
#include "tear/cut_script.h"
#include "tear/demo_scene.h"
#include "tear/device.h"
#include "tear/diff_meshes.h"
#include "tear/error.h"
#include "tear/find_frames.h"
#include "tear/frame_path.h"
#include "tear/frame_sink.h"
#include "tear/make_sheet.h"
#include "tear/mesh.h"
#include "tear/mesh_info.h"
#include "tear/read_mesh.h"
#include "tear/run_cuts.h"
#include "tear/simulation.h"
#include "tear/topology.h"
#include "tear/usd_layer.h"
#include "tear/validate_mesh.h"
#include "tear/write_mesh.h"
