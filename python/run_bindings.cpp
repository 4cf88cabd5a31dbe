// shellfrac.run(): what `shellfrac run` does (output/run.hpp), returning summary.json as a dict.
#include <atomic>
#include <chrono>
#include <functional>
#include <iostream>
#include <ostream>
#include <streambuf>
#include <type_traits>

#include "output/run.hpp"
#include "python/bindings.hpp"
#include "scene/build.hpp"

namespace shellfrac::python {

namespace {

// A stream that drops what it is given (run(..., log=False)).
class NullBuffer : public std::streambuf {
 protected:
  int overflow(int c) override { return traits_type::not_eof(c); }
};

// Whether output::RunOptions can be asked to stop between steps (a `std::function<bool()> should_stop`
// member, polled by the run driver). Detected at compile time, so that the module connects Ctrl-C to it
// as soon as the driver has it and builds without it until then.
template <class T, class = void>
struct HasShouldStop : std::false_type {};
template <class T>
struct HasShouldStop<T, std::void_t<decltype(std::declval<T&>().should_stop = std::function<bool()>())>>
    : std::true_type {};
constexpr bool kRunInterruptible = HasShouldStop<output::RunOptions>::value;

template <class Options>
void connect_interrupt(Options& options, std::atomic<bool>& interrupted) {
  if constexpr (HasShouldStop<Options>::value) {
    // As Simulation.advance_to: the GIL is taken for the signal check at most every 10 ms.
    options.should_stop = [&interrupted, last = std::chrono::steady_clock::now()]() mutable {
      if (interrupted) return true;
      const auto now = std::chrono::steady_clock::now();
      if (now - last < std::chrono::milliseconds(10)) return false;
      last = now;
      py::gil_scoped_acquire gil;
      if (PyErr_CheckSignals() != 0) interrupted = true;  // KeyboardInterrupt is now set on this thread
      return interrupted.load();
    };
  } else {
    (void)options;
    (void)interrupted;
  }
}

py::object run(const scene::Scene& scene, const std::string& out, int threads, bool log) {
  if (threads < 0) throw py::value_error("threads must be >= 0 (0: all cores), got " + std::to_string(threads));
  output::RunOptions options;
  options.out_dir = out;
  options.threads = threads;
  options.interactive = false;
  std::atomic<bool> interrupted{false};
  connect_interrupt(options, interrupted);
  NullBuffer null_buffer;
  std::ostream null_stream(&null_buffer);
  nlohmann::json summary;
  {
    py::gil_scoped_release nogil;
    const scene::Model model = scene::build(scene);
    summary = output::to_json(output::run_scene(model, options, log ? std::cerr : null_stream));
  }
  // The run stopped between steps and wrote its summary ("status": "interrupted"): raise the
  // KeyboardInterrupt that stopped it.
  if (interrupted) throw py::error_already_set();
  return json_to_python(summary.dump());
}

}  // namespace

void bind_run(py::module_& m) {
  m.attr("run_interruptible") = kRunInterruptible;
  m.def("_run", &run, py::arg("scene"), py::arg("out"), py::arg("threads") = 0, py::arg("log") = false,
        "Runs a Scene like `shellfrac run` (see shellfrac.run).");
}

}  // namespace shellfrac::python
