// qrm/qrm.hpp: the whole library, one header per facility.
//
// Circuits
//   registers.hpp        typed registers: position, direction, emission (Le), reflectance (rho), steps, out, ...
//   layout.hpp           layouts (compile-time qubit offsets), selectors bit/slice/qubits, controls when/on/off
//   gates.hpp            gate templates: x y z h ry rz phase u, unitary/real_unitary, add/increment,
//                        mux_ry, mux_unitary (multiplexed), prepare_uniform
//   circuit.hpp          seq, repeat, unroll, circuit<L, ...> with constexpr width / depth bound, run()
//   ops.hpp              the five primitive operations every backend implements (gate_sink)
//   program.hpp          run-time programs: record, replay, invert
//   metrics.hpp          width, logical depth, gate counts of a program
//   decompose.hpp        lowering to single-qubit gates + CNOTs (with ancillas), decomposed counts
//   qasm.hpp             OpenQASM 3 export (logical or decomposed) and import
// Backends
//   backends/dense.hpp   state_vector<S>: all 2^n amplitudes (S = complex or real, double or float)
//   backends/compact.hpp compact_state<S, L>: only the nonzero amplitudes (labels uint64_t or wide_label<W>)
//   measure.hpp          probabilities, distributions and samples through a layout
//   random.hpp           seeded, platform-independent generator; binomial sampling
// Quantum ray marching (the paper)
//   scene.hpp            voxel scenes (2D grids, 3D voxels): kind, normal, reflectance, emission
//   scene_io.hpp         the scene text format: parse_scene, load_scene, format_scene
//   paper_scenes.hpp     paper_4x4, paper_8x8 (SPEC.md section 3), box_2d(N) for scaling
//   directions.hpp       king_2d (8 directions), golden_spiral, antipodal_spiral, cube_directions
//   coins.hpp            Lambertian (2D paper matrix, 3D Hadamard/Fourier), boundary, specular coins
//   walk_model.hpp       the walk as classical data: coins per voxel, fixed-point shift, starts
//   walk.hpp             the A operator: ray_marching_circuit<...> (typed), make_walk_program (run-time),
//                        pruning levels, history variant
//   classical.hpp        exact branching path sum, Monte Carlo random walk
//   lightmap.hpp         exact light maps: faithful, history and classical per cell and channel
//   scaling.hpp          width formula, closed-form unpruned depth, per-layer depths, the scaling
//                        study's scenes, starts and sweep (qrm scaling, bench_scaling)
// Amplitude estimation
//   estimation/problem.hpp      estimation_problem (A program + good controls), bernoulli, sine_integral
//   estimation/grover.hpp       Grover operator Q = A S0 A^dagger S_chi, reflections, rescaling, qcoin coin
//   estimation/oracle.hpp       what an estimator asks for p_k: analytic_oracle, simulated_oracle<B>
//   estimation/result.hpp       estimation_result (estimate, interval, calls, rounds), to_radiance
//   estimation/fae.hpp          Faster Amplitude Estimation (Nakaji), exactly as SPEC.md section 5
//   estimation/iqae.hpp         Iterative Amplitude Estimation (Grinko et al.), Clopper-Pearson / Chernoff
//   estimation/mlae.hpp         Maximum-Likelihood Amplitude Estimation (Suzuki et al.), Fisher interval
//   estimation/canonical.hpp    canonical QPE-based amplitude estimation (Brassard et al.) + MLE
//   estimation/qcoin.hpp        quantum coin method (Shimada and Hachisuka 2020)
//   estimation/monte_carlo.hpp  classical Monte Carlo baseline on the same oracle
//   estimation/estimator.hpp    choosing an estimator at run time: estimator_settings, estimate_amplitude
// Rendering (3D)
//   render/voxelize.hpp  surface voxelization (rectangles, boxes, spheres): cornell_box, two_spheres
//   render/camera.hpp    pinhole camera: rays through pixel centres or jittered within pixels
//   render/dda.hpp       first voxel hit by a ray (Amanatides-Woo 3D DDA through the grid)
//   render/image.hpp     RGB float image tiles and their bit-exact merge, RMSE
//   render/render_classical.hpp  images on the walk's discretization: exact path sum, Monte Carlo,
//                        the paper's emulator (enumerate all paths, sample K); threads and tiles
//   render/quantum.hpp   with the circuit: estimated light maps (FAE on the simulated circuit), fully
//                        quantum 3D images, the amplitude-estimation hook for the emulator
//   render/experiments.hpp  convergence (error vs estimates) and cost (error vs time) studies
// Output
//   io/image.hpp         linear-RGB float images: tone mapping to sRGB, upsampling, error maps, stats
//   io/png.hpp           PNG writer (8-bit RGB/grey, stored deflate), crc32, adler32
//   io/pfm.hpp           PFM float images: exact write and read
//   io/svg_plot.hpp      SVG line/scatter plots (log axes, fitted slopes), least-squares fits
//   io/csv.hpp           results tables as CSV (round-trip numbers) and Markdown
//   io/atomic_file.hpp   whole-file writes via temp file + rename, creating directories
//   io/progress.hpp      thread-safe progress bar on stderr
#pragma once

#include "version.hpp"

#include "registers.hpp"
#include "layout.hpp"
#include "ops.hpp"
#include "gates.hpp"
#include "circuit.hpp"
#include "program.hpp"
#include "metrics.hpp"
#include "decompose.hpp"
#include "qasm.hpp"

#include "backends/dense.hpp"
#include "backends/compact.hpp"
#include "measure.hpp"
#include "random.hpp"

#include "scene.hpp"
#include "scene_io.hpp"
#include "paper_scenes.hpp"
#include "directions.hpp"
#include "coins.hpp"
#include "walk_model.hpp"
#include "walk.hpp"
#include "classical.hpp"
#include "lightmap.hpp"
#include "scaling.hpp"

#include "render/voxelize.hpp"
#include "render/camera.hpp"
#include "render/dda.hpp"
#include "render/image.hpp"
#include "render/render_classical.hpp"
#include "render/quantum.hpp"
#include "render/experiments.hpp"

#include "estimation/problem.hpp"
#include "estimation/grover.hpp"
#include "estimation/oracle.hpp"
#include "estimation/result.hpp"
#include "estimation/fae.hpp"
#include "estimation/iqae.hpp"
#include "estimation/mlae.hpp"
#include "estimation/canonical.hpp"
#include "estimation/qcoin.hpp"
#include "estimation/monte_carlo.hpp"
#include "estimation/estimator.hpp"

#include "io/image.hpp"
#include "io/png.hpp"
#include "io/pfm.hpp"
#include "io/svg_plot.hpp"
#include "io/csv.hpp"
#include "io/atomic_file.hpp"
#include "io/progress.hpp"
