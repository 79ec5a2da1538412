#pragma once
// The Python module's shared parts: arrays handed to numpy, Python's arguments checked as the
// command line checks its options, and a run's control (progress, Ctrl-C) with the GIL released.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <chrono>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "smokescan/core/error.hpp"
#include "smokescan/io/image.hpp"
#include "smokescan/pipeline/run_control.hpp"
#include "smokescan/sensor_config/sensor_kind.hpp"

namespace smokescan::python {
namespace py = pybind11;

/// A vector handed to numpy without a copy: the array owns it through a capsule.
template <class T>
inline py::array_t<T> ownedArray(std::vector<T>&& v)
{
    auto* held = new std::vector<T>(std::move(v));
    py::capsule owner(held, [](void* p) { delete static_cast<std::vector<T>*>(p); });
    return py::array_t<T>({py::ssize_t(held->size())}, {py::ssize_t(sizeof(T))}, held->data(), owner);
}

/// While the interpreter shuts down, a daemon thread still in a run must not take the GIL back

/// (Python would end the thread inside a destructor, and C++ would abort): it waits here for the

/// process to end instead.
inline void parkIfFinalizing()
{
#if PY_VERSION_HEX >= 0x030D0000
    while (Py_IsFinalizing()) std::this_thread::sleep_for(std::chrono::hours(1));
#else
    while (_Py_IsFinalizing()) std::this_thread::sleep_for(std::chrono::hours(1));
#endif
}

/// A time given from Python: a finite number, else an Error naming the option.
inline double finiteArg(double v, const char* option)
{
    if (!std::isfinite(v)) throw Error(option, "must be a finite number");
    return v;
}

/// A seed given from Python: a whole number from 0 to 2^64 − 1, as the command line's --seed.
inline uint64_t seedArg(const py::object& o)
{
    const char* what = "is not a seed (a whole number from 0 to 18446744073709551615)";
    if (py::isinstance<py::bool_>(o) || !py::hasattr(o, "__index__")) throw Error("--seed", what);
    try {
        return py::int_(o.attr("__index__")()).cast<uint64_t>();  // numpy's integers too
    } catch (const py::error_already_set&) {
        throw Error("--seed", what);
    } catch (const py::cast_error&) {
        throw Error("--seed", what);
    }
}

inline SensorModel modelArg(const std::string& name)
{
    if (const auto m = parseSensorModel(name)) return *m;
    throw Error("--model", "unknown sensor model '" + name + "' (paper, physical)");
}

/// A run's control from Python: progress to `progress` (a callable or None), and a stop when

/// Ctrl-C (or any signal whose handler raises) arrives. Called without the GIL; takes it.
struct PyControl {
    py::object progress;
    bool interrupted = false;
    explicit PyControl(py::object p) : progress(std::move(p))
    {
        if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
            throw py::type_error("progress must be a callable taking (done, total)");
    }
    RunControl control()
    {
        RunControl c;
        c.cancel = [this] {
            parkIfFinalizing();
            py::gil_scoped_acquire gil;
            if (PyErr_CheckSignals() != 0) {
                interrupted = true;  // the signal's exception is raised again once the run is out
                return true;
            }
            return false;
        };
        if (!progress.is_none())
            c.progress = [this](long long done, long long total) {
                parkIfFinalizing();
                py::gil_scoped_acquire gil;
                progress(done, total);
            };
        return c;
    }
};

/// Runs f without the GIL; a Ctrl-C that cancelled it comes back as Python's own exception.
template <class F>
auto released(PyControl& pc, F&& f)
{
    try {
        py::gil_scoped_release nogil;
        struct Park {
            ~Park() { parkIfFinalizing(); }  // before nogil takes the GIL back
        } park;
        return f(pc.control());
    } catch (const Cancelled&) {
        if (pc.interrupted) throw py::error_already_set();
        throw;
    }
}

/// A path given from Python: a str, bytes or os.PathLike, in the file system's encoding (names
/// that are not UTF-8 too); None is "" when `optional`, else an Error naming the option, as are
/// other types and a NUL inside.
inline std::string pathArg(const py::object& o, const char* option, bool optional = true)
{
    if (o.is_none()) {
        if (optional) return "";
        throw Error(option, "must be a path, not None");
    }
    if (!py::isinstance<py::str>(o) && !py::isinstance<py::bytes>(o) && !py::hasattr(o, "__fspath__"))
        throw Error(option, "must be a path (str, bytes or os.PathLike)");
    py::object b;
    try {
        b = py::module_::import("os").attr("fsencode")(o);
    } catch (const py::error_already_set&) {
        throw Error(option, "must be a path (str, bytes or os.PathLike)");
    }
    const std::string p = b.cast<std::string>();
    if (p.find('\0') != std::string::npos) throw Error(option, "holds a NUL character");
    if (p.empty()) throw Error(option, "names no file");
    return p;
}

/// An image as an H × W × channels float32 array over its own memory (no copy).
inline py::array imageArray(Image&& img)
{
    const py::ssize_t h = img.height, w = img.width, c = img.channels;
    return ownedArray(std::move(img.data)).reshape({h, w, c});
}

/// The module's parts, each in its own file: render (bind_render.cpp), the analyses of recorded
/// data (bind_analysis.cpp), volumes to and from numpy (bind_volume.cpp), the omnicam as a
/// rangefinder (bind_omni.cpp).
void bindRender(py::module_& m);
void bindAnalysis(py::module_& m);
void bindVolume(py::module_& m);
void bindOmni(py::module_& m);

}  // namespace smokescan::python
