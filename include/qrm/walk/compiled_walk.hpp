// qrm/walk/compiled_walk.hpp: include in exactly one source file of a program whose other source
// files are compiled with QRM_COMPILED_WALK defined. This file then compiles the walk's
// run-time builders (scenes and their parser, direction sets, coins, the walk model, the walk's
// tables, the classical references and cost formulas) and the walk of run-time widths
// (make_walk_program: walk_circuit<dynamic_walk_shape<2 or 3>>, recorded and pruned), each a
// function template instantiated once here, and the others call them instead of compiling their
// own copies (README, "Compiling the backends once": the same scheme as QRM_COMPILED_BACKENDS and
// <qrm/backends/compiled_backends.hpp>). A walk of static widths (ray_marching_circuit, any
// walk_circuit<Shape>) stays a template of its shape, compiled where it is used.
#pragma once

#include "circuit.hpp"
#include "classical.hpp"
#include "coins.hpp"
#include "cost.hpp"
#include "directions.hpp"
#include "model.hpp"
#include "paper_scenes.hpp"
#include "scene.hpp"
#include "scene_format.hpp"

namespace qrm {
QRM_DETAIL_SCENE_INSTANCES(template)
QRM_DETAIL_SCENE_FORMAT_INSTANCES(template)
QRM_DETAIL_PAPER_SCENES_INSTANCES(template)
QRM_DETAIL_DIRECTIONS_INSTANCES(template)
QRM_DETAIL_COINS_INSTANCES(template)
QRM_DETAIL_MODEL_INSTANCES(template)
QRM_DETAIL_WALK_CIRCUIT_INSTANCES(template)
QRM_DETAIL_CLASSICAL_INSTANCES(template)
QRM_DETAIL_COST_INSTANCES(template)
}  // namespace qrm
