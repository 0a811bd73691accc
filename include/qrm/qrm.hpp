// qrm/qrm.hpp: the whole library. Each layer is a folder with an umbrella header of the same
// name; a layer includes only layers listed before it (io needs none of them):
//   support.hpp     random numbers, parallel jobs
//   circuit.hpp     typed registers, layouts, gate templates, circuits, programs, QASM
//   backends.hpp    the backend concept, dense and compact simulators, measurement
//   estimation.hpp  amplitude estimators
//   noise.hpp       noise models, quantum trajectories, the noisy oracle
//   resources.hpp   fault-tolerant cost: Clifford+T counts, surface-code qubits and time
//   walk.hpp        quantum ray marching: scenes, coins, the walk circuit, classical references
//   render.hpp      3D images: voxelizer, camera, classical and quantum renderers
//   io.hpp          PNG, PFM, SVG, CSV, atomic files, progress
// Include a single layer (e.g. <qrm/circuit.hpp> and <qrm/backends/dense.hpp>) to pay only for it.
//
// Non-template functions in these headers, and the member functions of non-template classes,
// are written `template <int = 0>` so that they are compiled only in the translation units that
// call them: including a layer stays cheap (one-line and constexpr functions excepted: they call
// nothing worth deferring). Passed as a predicate, such a function is named `f<>`. Where
// such a function uses a helper class template, it passes its parameter on (`template <int
// Deferred = 0>` ... `helper<Deferred>`): a helper named with a fixed argument would be
// instantiated by the compiler where the header is read, used or not. clang goes further: it
// instantiates the standard library's constexpr members (all of std::vector's in C++20) that a
// template calls on a non-dependent type where the template is defined. The heaviest deferred
// code (the program, the lowerer, the QASM parser, compact_state, build_walk_tables) therefore
// names its containers through `detail::deferred<T, Deferred>`, which is T spelled as a
// dependent type.
#pragma once

#include "version.hpp"

#include "support.hpp"
#include "circuit.hpp"
#include "backends.hpp"
#include "estimation.hpp"
#include "noise.hpp"
#include "resources.hpp"
#include "walk.hpp"
#include "render.hpp"
#include "io.hpp"
