// qrm/render.hpp: 3D images on the walk's discretization. (The convergence and cost studies of
// `qrm figures` live beside the tool: examples/qrm/studies.hpp.)
//   render/voxelize.hpp    surface voxelization (rectangles, boxes, spheres): cornell_box, two_spheres
//   render/camera.hpp      pinhole camera: rays through pixel centres or jittered within pixels
//   render/dda.hpp         first voxel hit by a ray (Amanatides-Woo 3D DDA through the grid)
//   render/tiles.hpp       RGB float image tiles and their bit-exact merge, RMSE
//   render/classical.hpp   exact path sum, Monte Carlo, the paper's emulator (enumerate all paths,
//                          sample K); threads and tiles
//   render/quantum.hpp     with the circuit: estimated light maps (FAE on the simulated circuit), fully
//                          quantum 3D images, the amplitude-estimation hook for the emulator
#pragma once

#include "render/voxelize.hpp"
#include "render/camera.hpp"
#include "render/dda.hpp"
#include "render/tiles.hpp"
#include "render/classical.hpp"
#include "render/quantum.hpp"
