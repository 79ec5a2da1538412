// smokescan.read_volume / write_volume: an OpenVDB density grid to and from a numpy array with
// its index-to-world transform (media/dense_voxels.hpp).
#include <pybind11/stl.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <system_error>

#include "module_support.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/media/dense_voxels.hpp"

namespace smokescan::python {
namespace {
namespace fs = std::filesystem;

py::array_t<double> matrixArray(const std::array<double, 16>& m)
{
    py::array_t<double> a({4, 4});
    auto v = a.mutable_unchecked<2>();
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) v(r, c) = m[size_t(4 * r + c)];
    return a;
}

/// A 4 × 4 matrix from Python (any array-like of numbers), else an Error naming the option.
std::array<double, 16> matrixArg(const py::object& o, const char* option)
{
    py::array_t<double, py::array::c_style | py::array::forcecast> a;
    try {
        a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(o);
    } catch (const py::error_already_set&) {
    }
    if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4)
        throw Error(option, "must be a 4×4 matrix of numbers");
    std::array<double, 16> m{};
    for (size_t i = 0; i < 16; ++i) m[i] = a.data()[i];
    return m;
}

}  // namespace

void bindVolume(py::module_& m)
{
    m.def(
        "read_volume",
        [](const py::object& path, const std::string& grid, double scale) {
            const std::string file = pathArg(path, "path", false);
            if (!(scale > 0 && scale <= limits::kDensity)) throw Error("scale", "must lie in (0, 1e6]");
            DenseVoxels d;
            {
                py::gil_scoped_release nogil;
                d = toDense(DensityGrid::loadVdb(file, {grid, scale}), file);
            }
            const std::array<long long, 3> size = d.size;
            py::array_t<float> values = ownedArray(std::move(d.values));
            py::tuple out(2);
            out[0] = values.reshape({py::ssize_t(size[0]), py::ssize_t(size[1]), py::ssize_t(size[2])});
            out[1] = matrixArray(d.index_to_world);
            return out;
        },
        py::arg("path"), py::arg("grid") = "density", py::arg("scale") = 1.0,
        "A scalar grid of a .vdb file (float or double; `grid` \"\" takes the first) as (density, index_to_world): "
        "a float32 array over the box of its non-zero voxels, density[a, b, c] the voxel whose centre is at "
        "index_to_world @ (a, b, c, 1) [m]; values × scale");
    m.def(
        "write_volume",
        [](const py::object& path, const py::object& density, const py::object& index_to_world,
           const std::string& grid) {
            const std::string file = pathArg(path, "path", false);
            if (grid.empty()) throw Error("grid", "must not be empty");
            std::error_code ec;
            if (fs::symlink_status(file, ec).type() != fs::file_type::not_found)
                throw Error(file, "exists; write_volume writes a new file");
            // The array's shape and kind before any copy: a view of a huge array is refused as it is.
            const py::array any = py::array::ensure(density);
            if (!any || any.ndim() != 3) throw Error("density", "must be a 3-D array of numbers");
            const char kind = any.dtype().kind();
            if (kind != 'f' && kind != 'i' && kind != 'u')
                throw Error("density",
                            std::string("must hold real numbers (its dtype is ") +
                                py::str(any.dtype()).cast<std::string>() + ")");
            DenseVoxels d;
            long long n = 1;
            for (size_t i = 0; i < 3; ++i) {
                d.size[i] = any.shape(py::ssize_t(i));
                n *= std::max<long long>(1, d.size[i]);
                if (n > limits::kDenseVoxels)
                    throw Error("density",
                                "holds more than the " + std::to_string(limits::kDenseVoxels) +
                                    " voxels a dense block may hold");
            }
            d.index_to_world = matrixArg(index_to_world, "index_to_world");
            const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(any);
            if (!a) throw py::error_already_set();  // numpy's own error (memory)
            d.values.assign(a.data(), a.data() + a.size());
            py::gil_scoped_release nogil;
            DensityGrid::writeVdb(file, {{grid, fromDense(d, "density")}});
        },
        py::arg("path"), py::arg("density"), py::arg("index_to_world"), py::arg("grid") = "density",
        "Writes a 3-D array of densities (finite, >= 0) as an OpenVDB grid named `grid` in a new .vdb file "
        "(atomically): density[a, b, c] is the voxel whose centre is at index_to_world @ (a, b, c, 1) [m], "
        "a 4×4 affine map whose voxels are cubes (e.g. np.diag([h, h, h, 1]) with the origin in its last column); "
        "zeros stay inactive. An existing path is refused");
}

}  // namespace smokescan::python
