// qrm/qrm.hpp: the whole library. One header per facility:
//   registers.hpp        typed registers (position, direction, emission, reflectance, steps, out, ...)
//   layout.hpp           layouts, qubit selectors (bit, slice, qubits), controls (when, on, off)
//   gates.hpp            gate templates: x y z h ry rz phase u, unitary, add, mux_ry, mux_unitary,
//                        prepare_uniform
//   circuit.hpp          seq, repeat, unroll, circuit<L, ...>, compile-time metrics, run()
//   ops.hpp              the primitive instruction set every backend implements (gate_sink)
//   program.hpp          run-time programs: record, replay, invert
//   backends/dense.hpp   state_vector<S>: the dense backend
//   measure.hpp          probabilities, distributions and samples through a layout
//   random.hpp           seeded generator, binomial sampling
//   render/image.hpp     minimal RGB float image, tiles and their bit-exact merge, RMSE
//   render/camera.hpp    pinhole camera: rays through pixel centres or jittered within pixels
//   render/dda.hpp       first voxel hit by a ray (Amanatides-Woo 3D DDA through the grid)
//   render/voxelize.hpp  surface voxelization (rectangles, boxes, spheres); cornell_box, two_spheres
//   render/render_classical.hpp  images on the walk's discretization: exact path sum, Monte Carlo,
//                        the paper's emulator (enumerate all paths, sample K); threads and tiles
#pragma once

#include "version.hpp"
#include "registers.hpp"
#include "layout.hpp"
#include "ops.hpp"
#include "gates.hpp"
#include "circuit.hpp"
#include "program.hpp"
#include "random.hpp"
#include "measure.hpp"
#include "backends/dense.hpp"
#include "render/image.hpp"
#include "render/camera.hpp"
#include "render/dda.hpp"
#include "render/voxelize.hpp"
#include "render/render_classical.hpp"
