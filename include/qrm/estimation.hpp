// qrm/estimation.hpp: amplitude estimation on any circuit (A program + good controls).
//   estimation/problem.hpp      estimation_problem, bernoulli, sine_integral
//   estimation/grover.hpp       Grover operator Q = A S0 A^dagger S_chi, reflections, rescaling, qcoin coin
//   estimation/oracle.hpp       what an estimator asks for p_k: analytic_oracle, simulated_oracle<B>
//   estimation/result.hpp       estimation_result (estimate, interval, calls, rounds), to_radiance
//   estimation/fae.hpp          Faster Amplitude Estimation (Nakaji)
//   estimation/iqae.hpp         Iterative Amplitude Estimation (Grinko et al.), Clopper-Pearson / Chernoff
//   estimation/chebae.hpp       Chebyshev amplitude estimation, ChebAE (Rall and Fuller 2023)
//   estimation/mlae.hpp         Maximum-Likelihood Amplitude Estimation (Suzuki et al.), Fisher interval
//   estimation/canonical.hpp    canonical QPE-based amplitude estimation (Brassard et al.) + MLE
//   estimation/qcoin.hpp        quantum coin method (Shimada and Hachisuka 2020)
//   estimation/monte_carlo.hpp  classical Monte Carlo baseline on the same oracle
//   estimation/estimator.hpp    choosing an estimator at run time: estimator_settings, estimate_amplitude
#pragma once

#include "estimation/problem.hpp"
#include "estimation/grover.hpp"
#include "estimation/oracle.hpp"
#include "estimation/result.hpp"
#include "estimation/fae.hpp"
#include "estimation/iqae.hpp"
#include "estimation/chebae.hpp"
#include "estimation/mlae.hpp"
#include "estimation/canonical.hpp"
#include "estimation/qcoin.hpp"
#include "estimation/monte_carlo.hpp"
#include "estimation/estimator.hpp"
