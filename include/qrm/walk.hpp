// qrm/walk.hpp: quantum ray marching, the paper's walk (scenes, coins, the A operator, references).
//   walk/scene.hpp         voxel scenes (2D grids, 3D voxels): kind, normal, reflectance, emission
//   walk/scene_format.hpp  the scene text format: parse_scene, load_scene, format_scene
//   walk/paper_scenes.hpp  paper_4x4, paper_8x8 (the paper's Fig. 4 rooms), box_2d(N) for scaling
//   walk/directions.hpp    king_2d (8 directions), golden_spiral, antipodal_spiral, cube_directions
//   walk/coins.hpp         Lambertian (2D paper matrix, 3D Hadamard/Fourier), boundary, specular coins
//   walk/model.hpp         the walk as classical data: coins per voxel, fixed-point shift, starts
//   walk/circuit.hpp       the A operator: ray_marching_circuit<...> (typed), make_walk_program (run-time),
//                          pruning levels, history variant
//   walk/classical.hpp     exact branching path sum, Monte Carlo random walk
//   walk/lightmap.hpp      exact light maps: faithful, history and classical per cell and channel
//   walk/cost.hpp          width formula, closed-form unpruned depth, per-layer depths
#pragma once

#include "walk/scene.hpp"
#include "walk/scene_format.hpp"
#include "walk/paper_scenes.hpp"
#include "walk/directions.hpp"
#include "walk/coins.hpp"
#include "walk/model.hpp"
#include "walk/circuit.hpp"
#include "walk/classical.hpp"
#include "walk/lightmap.hpp"
#include "walk/cost.hpp"
