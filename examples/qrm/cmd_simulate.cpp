// examples/qrm/cmd_simulate.cpp: `qrm simulate`, a general circuit (an OpenQASM 3 file or a
// random gate suite) on the dense or the compact backend, with or without gate fusion, timed, and
// optionally the final state written as raw amplitudes (to check against another simulator).
#include <algorithm>
#include <bit>
#include <chrono>
#include <cinttypes>
#include <complex>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <qrm/backends/compact.hpp>
#include <qrm/backends/dense.hpp>
#include <qrm/backends/detail/dense_batched.hpp>  // detail::resolve_simd: the level the kernels run
#include <qrm/circuit/fuse.hpp>
#include <qrm/circuit/qasm.hpp>
#include <qrm/io/atomic_file.hpp>
#include <qrm/support/random.hpp>
#include <span>
#include <sstream>
#include <thread>
#include <string>
#include <vector>

#include "commands.hpp"
#include "json.hpp"
#include "random_suite.hpp"

namespace qrm_cli {

namespace {

qrm::program read_qasm(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw usage_error("--qasm: cannot read '" + path + "'");
  std::ostringstream text;
  text << f.rdbuf();
  try {
    return qrm::from_qasm(text.str());
  } catch (const std::exception& e) {
    throw usage_error("--qasm " + path + ": " + e.what());
  }
}

struct timed_run {
  std::vector<double> seconds;  // one per repetition
  double norm = 0;
};
struct simulation {
  timed_run run, plain;      // plain: the unfused program, with --compare
  double difference = 0;     // largest |run - plain| over the amplitudes
};

template <class State>
timed_run run_timed(State& s, const qrm::program& p, unsigned repeat) {
  timed_run r;
  for (unsigned i = 0; i < repeat; ++i) {
    s.set_basis_state(0);
    const auto t0 = std::chrono::steady_clock::now();
    qrm::run(s, p);
    r.seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  r.norm = s.norm_squared();
  return r;
}

// What the run needs besides the circuit.
struct run_settings {
  bool compact = false;
  unsigned threads = 1;
  unsigned repeat = 3;
  qrm::simd_level simd = qrm::simd_level::automatic;
  qrm::float_math math = qrm::float_math::double_precision;
  std::uint64_t chunk_bytes = 0;  // dense backend: runs of ops applied chunk by chunk (0: op by op)
  double chunk_min_passes = qrm::dense_options{}.chunk_min_passes;  // ... when they make this many passes
  std::string state_out;  // empty: do not write the state
};

// The 2^n amplitudes as raw little-endian numbers of the state's own type (complex: real part,
// then imaginary part), written whole or not at all.
template <class S>
void write_state(const std::string& path, std::span<const S> amps) {
  qrm::io::write_file_atomically(path, [&](qrm::io::file_sink& out) {
    std::vector<unsigned char> buf(sizeof(S) * 4096);
    for (std::size_t i = 0; i < amps.size(); i += 4096) {
      const std::size_t count = std::min<std::size_t>(4096, amps.size() - i);
      std::memcpy(buf.data(), amps.data() + i, count * sizeof(S));
      if constexpr (std::endian::native == std::endian::big) {
        constexpr std::size_t word = qrm::detail::scalar_traits<S>::is_complex ? sizeof(S) / 2 : sizeof(S);
        for (std::size_t b = 0; b < count * sizeof(S); b += word) std::reverse(buf.begin() + b, buf.begin() + b + word);
      }
      out.write(buf.data(), count * sizeof(S));
    }
  });
}

template <class S, class State>
std::vector<S> dense_copy(const State& s) {
  if constexpr (requires { s.to_dense(); })
    return s.to_dense();
  else
    return std::vector<S>(s.amplitudes().begin(), s.amplitudes().end());
}

// `program` timed; with `plain`, that one too, and the two final states compared.
template <class S, class State, class Make>
simulation simulate_on(const qrm::program& program, const qrm::program* plain, const run_settings& rs, Make make) {
  simulation r;
  State s = make(program.width());
  r.run = run_timed(s, program, rs.repeat);
  if (plain) {
    State t = make(plain->width());
    r.plain = run_timed(t, *plain, rs.repeat);
    const std::vector<S> a = dense_copy<S>(s), b = dense_copy<S>(t);
    for (std::size_t i = 0; i < a.size(); ++i) r.difference = std::max(r.difference, static_cast<double>(std::abs(a[i] - b[i])));
  }
  if (!rs.state_out.empty()) {
    const std::vector<S> a = dense_copy<S>(s);
    write_state<S>(rs.state_out, a);
  }
  return r;
}

template <class S>
simulation simulate(const qrm::program& program, const qrm::program* plain, const run_settings& rs) {
  if (rs.compact)
    return simulate_on<S, qrm::compact_state<S>>(program, plain, rs, [](std::size_t n) { return qrm::compact_state<S>(n); });
  qrm::dense_options o;
  o.threads = rs.threads;
  o.simd = rs.simd;
  o.math = rs.math;
  o.chunk_bytes = rs.chunk_bytes;
  o.chunk_min_passes = rs.chunk_min_passes;
  return simulate_on<S, qrm::state_vector<S>>(program, plain, rs, [&](std::size_t n) { return qrm::state_vector<S>(n, o); });
}

simulation simulate_scalar(const std::string& scalar, const qrm::program& program, const qrm::program* plain,
                           const run_settings& rs) {
  if (scalar == "complex-double") return simulate<std::complex<double>>(program, plain, rs);
  if (scalar == "complex-float") return simulate<std::complex<float>>(program, plain, rs);
  if (scalar == "double") return simulate<double>(program, plain, rs);
  return simulate<float>(program, plain, rs);
}

// Fusion options for the dense backend's chunked runs of the --scalar type (qrm::dense_fusion_options).
qrm::fusion_options within_chunks(const std::string& scalar, qrm::fusion_options fo, std::uint64_t chunk_bytes) {
  qrm::dense_options d;
  d.chunk_bytes = chunk_bytes;
  if (scalar == "complex-double") return qrm::dense_fusion_options<std::complex<double>>(fo, d);
  if (scalar == "complex-float") return qrm::dense_fusion_options<std::complex<float>>(fo, d);
  if (scalar == "double") return qrm::dense_fusion_options<double>(fo, d);
  return qrm::dense_fusion_options<float>(fo, d);
}

double fastest(const timed_run& r) { return *std::min_element(r.seconds.begin(), r.seconds.end()); }

}  // namespace

flag_table simulate_flags() {
  const char* in = "circuit (one of)";
  const char* run = "simulation";
  const char* out = "output";
  return {
      {"qasm", "FILE", "", "an OpenQASM 3 file (e.g. from qrm circuit --qasm F --decomposed)", in},
      {"random", "N", "", "a random suite on N qubits: H, Ry, CX, CCX, C^4 X, uniformly mixed", in},
      {"gates", "G", "300", "with --random: the number of gates", in},
      {"seed", "S", "1", "with --random: the seed", in},
      {"scalar", "complex-double|complex-float|double|float", "complex-double",
       "amplitude type (real types need a circuit of real gates)", run},
      {"backend", "dense|compact", "dense",
       "the dense state vector, or the compact backend (only the nonzero amplitudes; one thread)", run},
      {"fuse", "auto|K|on|off", "auto",
       "multiply runs of gates on at most K qubits (1..6) into one matrix; auto (or on): the K from 2 to 6 whose "
       "fused circuit qrm::estimated_passes rates cheapest",
       run},
      {"fuse-scope", "auto|runs|program", "auto",
       "dense backend with chunks: fuse within the runs it applies chunk by chunk, each block keeping to its run's "
       "qubits (fusion adds no trip to memory), or across the whole program; auto: the one qrm::estimated_passes rates "
       "cheaper (qrm::fuse_cheaper_scope)",
       run},
      {"threads", "T", "0", "threads of the dense backend (0: every core)", run},
      {"simd", "auto|generic|avx2|avx512", "auto",
       "vector instructions of the fused-matrix kernels (a level the CPU lacks runs the best below it)", run},
      {"arithmetic", "double|float", "double",
       "with --scalar complex-float: what the matrix kernels compute in (float: as qsim, about 2x faster, the norm "
       "drifts more)",
       run},
      {"chunk", "KIB|off", "1024",
       "dense backend: runs of ops whose qubits fit a chunk of KIB KiB are applied chunk by chunk, one pass over "
       "memory per run (about the L2 cache; off: every op its own pass)",
       run},
      {"chunk-passes", "P", "2",
       "dense backend: chunk a run only when its ops would make at least P passes over memory one by one (0: every "
       "run that fits a chunk)",
       run},
      {"repeat", "R", "3", "runs of the circuit; the fastest is reported", run},
      {"compare", "", "", "also run without fusion: both times and the largest amplitude difference", run},
      {"format", "json|text", "json", "output on stdout", out},
      {"state-out", "FILE", "",
       "write the final state: 2^n amplitudes as raw little-endian numbers of the --scalar type (complex: real, "
       "imaginary)",
       out},
  };
}

int cmd_simulate(args& a) {
  a.allow(simulate_flags());
  if (a.has("qasm") == a.has("random")) throw usage_error("give exactly one of --qasm FILE and --random N");
  if (!a.has("random") && (a.has("gates") || a.has("seed")))
    throw usage_error(std::string("--") + (a.has("gates") ? "gates" : "seed") + " applies to --random N");
  const std::string scalar = a.str("scalar", "complex-double");
  if (scalar != "complex-double" && scalar != "complex-float" && scalar != "double" && scalar != "float")
    throw usage_error("--scalar must be complex-double, complex-float, double or float, got '" + scalar + "'");
  const std::string backend = a.str("backend", "dense");
  if (backend != "dense" && backend != "compact")
    throw usage_error("--backend must be dense or compact, got '" + backend + "'");
  const bool compact = backend == "compact";
  if (compact && a.has("threads") && a.str("threads", "") != "1")
    throw usage_error("--threads applies to --backend dense; the compact backend runs on one thread");
  if (compact && a.has("simd")) throw usage_error("--simd applies to --backend dense");
  const std::string arithmetic = a.str("arithmetic", "double");
  if (arithmetic != "double" && arithmetic != "float")
    throw usage_error("--arithmetic must be double or float, got '" + arithmetic + "'");
  if (arithmetic == "float" && (scalar != "complex-float" || compact))
    throw usage_error("--arithmetic float applies to --scalar complex-float on --backend dense");
  const std::string fuse_arg = a.str("fuse", "auto") == "on" ? "auto" : a.str("fuse", "auto");
  const bool fuse_auto = fuse_arg == "auto";
  unsigned fuse_width = 0;
  if (fuse_auto) {
    fuse_width = 3;  // replaced by the width fuse_cheapest chooses
  } else if (fuse_arg != "off") {
    if (fuse_arg.empty() || fuse_arg.find_first_not_of("0123456789") != std::string::npos || fuse_arg.size() > 2 ||
        std::stoi(fuse_arg) < 1 || std::stoi(fuse_arg) > 6)
      throw usage_error("--fuse must be a width 1..6, auto, on or off, got '" + fuse_arg + "'");
    fuse_width = static_cast<unsigned>(std::stoi(fuse_arg));
  }
  const std::string fuse_scope = a.str("fuse-scope", "auto");
  if (fuse_scope != "auto" && fuse_scope != "runs" && fuse_scope != "program")
    throw usage_error("--fuse-scope must be auto, runs or program, got '" + fuse_scope + "'");
  if (a.has("fuse-scope") && fuse_width == 0) throw usage_error("--fuse-scope applies to fusion; --fuse is off");
  const auto threads = static_cast<unsigned>(a.integer("threads", 0, 0, 1024));
  const auto repeat = static_cast<unsigned>(a.integer("repeat", 3, 1, 1000));
  const bool compare = a.flag("compare");
  const std::string simd_arg = a.str("simd", "auto");
  qrm::simd_level simd = qrm::simd_level::automatic;
  if (simd_arg == "generic") simd = qrm::simd_level::generic;
  else if (simd_arg == "avx2") simd = qrm::simd_level::avx2;
  else if (simd_arg == "avx512") simd = qrm::simd_level::avx512;
  else if (simd_arg != "auto") throw usage_error("--simd must be auto, generic, avx2 or avx512, got '" + simd_arg + "'");
  const std::string chunk_arg = a.str("chunk", "1024");
  std::uint64_t chunk_kib = 0;
  if (chunk_arg != "off") {
    if (chunk_arg.empty() || chunk_arg.size() > 7 || chunk_arg.find_first_not_of("0123456789") != std::string::npos ||
        std::stoull(chunk_arg) < 1 || std::stoull(chunk_arg) > 1048576)
      throw usage_error("--chunk must be a size in KiB from 1 to 1048576, or off, got '" + chunk_arg + "'");
    chunk_kib = std::stoull(chunk_arg);
  }
  if (compact && a.has("chunk")) throw usage_error("--chunk applies to --backend dense");
  if (a.has("fuse-scope") && (compact || chunk_kib == 0))
    throw usage_error("--fuse-scope applies to the dense backend with chunks (--chunk KIB)");
  const double chunk_passes = a.number("chunk-passes", qrm::dense_options{}.chunk_min_passes);
  if (chunk_passes < 0 || chunk_passes > 1000)
    throw usage_error("--chunk-passes must be a number of passes from 0 to 1000, got '" + a.str("chunk-passes", "") + "'");
  if (compact && a.has("chunk-passes")) throw usage_error("--chunk-passes applies to --backend dense");
  if (chunk_kib == 0 && a.has("chunk-passes")) throw usage_error("--chunk-passes needs chunks; it does nothing with --chunk off");
  const char* simd_used = qrm::simd_level_name(qrm::detail::resolve_simd(simd));
  const std::string format = a.str("format", "json");
  if (format != "json" && format != "text") throw usage_error("--format must be json or text, got '" + format + "'");
  if (compare && fuse_width == 0) throw usage_error("--compare compares fused with unfused; it needs --fuse K or auto, not off");

  std::string source;
  qrm::program p;
  if (a.has("qasm")) {
    source = a.str("qasm", "");
    p = read_qasm(source);
  } else {
    const auto n = static_cast<std::size_t>(a.integer("random", 20, 2, 40));
    const auto gates = static_cast<std::size_t>(a.integer("gates", 300, 1, 100000000));
    const auto seed = static_cast<std::uint64_t>(a.integer("seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
    source = "random suite, " + std::to_string(n) + " qubits, " + std::to_string(gates) + " gates, seed " +
             std::to_string(seed);
    p = random_gate_suite(n, gates, seed);
  }
  if ((scalar == "double" || scalar == "float") && !p.is_real())
    throw usage_error("--scalar " + scalar + " stores real amplitudes, but " +
                      (a.has("qasm") ? "'" + source + "'" : std::string("the circuit")) +
                      " has complex gates; use complex-double or complex-float");
  const std::string state_out = a.str("state-out", "");
  if (!compact && p.width() > 34)
    throw usage_error("the circuit has " + std::to_string(p.width()) +
                      " qubits; the dense backend is limited to 34 here (--backend compact stores only nonzero amplitudes)");
  if (compact && p.width() > 64)
    throw usage_error("the circuit has " + std::to_string(p.width()) + " qubits; the compact backend's labels hold 64");
  if (!state_out.empty() && p.width() > 34)
    throw usage_error("--state-out writes all 2^" + std::to_string(p.width()) + " amplitudes; it is limited to 34 qubits");

  const unsigned used_threads = compact ? 1u : threads ? threads : std::max(1u, std::thread::hardware_concurrency());
  qrm::fusion_report rep;
  double fuse_seconds = 0;
  qrm::program fused;
  unsigned fuse_run_qubits = 0;  // fused within runs of chunks of this many qubits (0: the whole program)
  if (fuse_width) {
    const auto t0 = std::chrono::steady_clock::now();
    qrm::fusion_options fo{fuse_width};
    if (!compact && fuse_scope != "program") fo = within_chunks(scalar, fo, chunk_kib << 10);
    const bool compare_scopes = fuse_scope == "auto";
    if (fuse_auto)
      fused = qrm::fuse_cheapest(p, fo, &rep, compare_scopes);
    else
      fused = compare_scopes ? qrm::fuse_cheaper_scope(p, fo, &rep) : qrm::fuse(p, fo, &rep);
    fuse_run_qubits = rep.chunk_qubits;
    fuse_width = rep.max_qubits;
    fuse_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  run_settings rs;
  rs.compact = compact;
  rs.threads = used_threads;
  rs.repeat = repeat;
  rs.simd = simd;
  rs.math = arithmetic == "float" ? qrm::float_math::single_precision : qrm::float_math::double_precision;
  rs.chunk_bytes = chunk_kib << 10;
  rs.chunk_min_passes = chunk_passes;
  rs.state_out = state_out;
  const simulation sim = simulate_scalar(scalar, fuse_width ? fused : p, compare ? &p : nullptr, rs);
  const timed_run& main_run = sim.run;
  const timed_run& plain = sim.plain;
  const double difference = sim.difference;

  if (format == "text") {
    std::printf("circuit   %s: %zu qubits, %zu ops\n", source.c_str(), p.width(), p.size());
    if (fuse_width)
      std::printf("fused     %zu ops (%zu blocks of up to %u qubits%s, %s; estimated %.4g passes) in %.3g s\n",
                  rep.ops_out, rep.fused_blocks, fuse_width, fuse_auto ? ", the width chosen by cost" : "",
                  fuse_run_qubits ? ("within runs of " + std::to_string(fuse_run_qubits) + " qubits").c_str()
                                  : "across the program",
                  rep.estimated_passes, fuse_seconds);
    if (compact)
      std::printf("run       %s, compact backend: %.6g s (fastest of %u)\n", scalar.c_str(), fastest(main_run), repeat);
    else
      std::printf("run       %s, %u thread(s), %s kernels%s, chunks of %s: %.6g s (fastest of %u)\n", scalar.c_str(),
                  used_threads, simd_used, arithmetic == "float" ? " in float arithmetic" : "",
                  chunk_kib ? (std::to_string(chunk_kib) + " KiB").c_str() : "off", fastest(main_run), repeat);
    if (compare)
      std::printf("unfused   %.6g s: fused takes %.3gx the unfused time; largest |difference| %.3g\n", fastest(plain),
                  fastest(main_run) / fastest(plain), difference);
    std::printf("norm      %.17g\n", main_run.norm);
    if (!state_out.empty()) std::printf("state     %s\n", state_out.c_str());
    return 0;
  }
  json_object j;
  j.add("circuit", source).add("qubits", p.width()).add("gates", p.size()).add("ops", p.size()).add("scalar", scalar);
  j.add("backend", backend).add("threads", used_threads);
  if (!compact) j.add("simd", simd_used);
  if (!compact) {
    if (chunk_kib)
      j.add("chunk_kib", chunk_kib).add("chunk_min_passes", chunk_passes);
    else
      j.add("chunk_kib", "off");
  }
  if (scalar == "complex-float" && !compact) j.add("arithmetic", arithmetic);
  j.add("repeat", repeat);
  if (fuse_width) {
    j.add("fuse", fuse_width).add("fuse_width_chosen", fuse_auto).add("estimated_passes", rep.estimated_passes);
    j.add("fuse_scope", fuse_run_qubits ? "runs" : "program");
    if (fuse_run_qubits) j.add("fuse_run_qubits", fuse_run_qubits);
    j.add("fused_ops", rep.ops_out).add("fused_blocks", rep.fused_blocks);
    j.add("blocks_by_width", json_array::of(rep.blocks_by_width)).add("fuse_seconds", fuse_seconds);
  } else {
    j.add("fuse", "off").add("fused_ops", p.size());  // unfused: every gate is its own op
  }
  j.add("seconds", fastest(main_run)).add("seconds_each", json_array::of(main_run.seconds)).add("norm", main_run.norm);
  if (compare) {
    j.add("unfused_seconds", fastest(plain)).add("unfused_seconds_each", json_array::of(plain.seconds));
    j.add("fused_over_unfused", fastest(main_run) / fastest(plain)).add("max_abs_difference", difference);
  }
  if (!state_out.empty()) j.add("state_out", state_out);
  std::printf("%s\n", j.str().c_str());
  return 0;
}

}  // namespace qrm_cli
