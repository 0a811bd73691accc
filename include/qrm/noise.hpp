// qrm/noise.hpp: the walk on a noisy (not error-corrected) quantum computer.
//   noise/model.hpp         noise_model: depolarizing, T1/T2 relaxation, readout; presets
//   noise/channels.hpp      noisy_circuit: a circuit's gates and channels as events, at gate level
//                           (decomposed, ASAP schedule) or logical level (one channel per op)
//   noise/trajectories.hpp  quantum trajectories on the dense backend, readout-aware probabilities
//   noise/fused_trajectories.hpp  the same trajectories on fused gates, the errors that fire folded in
//   noise/oracle.hpp        noisy_oracle (trajectories) and global_noise_oracle (closed form): p_k
//                           of Q^k A under noise, for every estimator
#pragma once

#include "noise/model.hpp"
#include "noise/channels.hpp"
#include "noise/trajectories.hpp"
#include "noise/fused_trajectories.hpp"
#include "noise/oracle.hpp"
