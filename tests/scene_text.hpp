#pragma once
// Scene files as text for tests and benchmarks: the pieces the renderer's tests share (a light, a
// camera, a box or .vdb of smoke), written once, so that a test states only what differs.
#include <array>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

namespace smokescan::test {

/// A number as TOML text that parses back to the same double (17 significant digits).
inline std::string tomlNumber(double v)
{
    std::ostringstream o;
    o << std::setprecision(17) << v;
    return o.str();
}

/// [x, y, z] as a TOML array.
inline std::string tomlVec(const std::array<double, 3>& v)
{
    return "[" + tomlNumber(v[0]) + ", " + tomlNumber(v[1]) + ", " + tomlNumber(v[2]) + "]";
}

/// A grey medium of σ_t [1/m per density unit] at every band, as a smoke table's inline `medium`;
/// g left out (NaN) is the medium's default.
inline std::string greyMedium(double sigma_t, double albedo, double g = std::nan(""))
{
    const std::string s = tomlNumber(sigma_t);
    return "{ sigma_t_550 = " + s + ", sigma_t_785 = " + s + ", sigma_t_905 = " + s +
        ", albedo = " + tomlNumber(albedo) + (std::isnan(g) ? std::string() : ", g = " + tomlNumber(g)) + " }";
}

/// A scene's text, built from its pieces in the order they are added.
class SceneText {
public:
    /// Uniform ambient light of `radiance` [W/(m²·sr)].
    SceneText& ambient(double radiance)
    {
        text_ += "[[lights]]\nname = \"sky\"\nkind = \"ambient\"\nradiance = " + tomlNumber(radiance) + "\n";
        return *this;
    }
    /// A point light at `position` radiating power_w × efficiency [W].
    SceneText& point(const std::array<double, 3>& position, double power_w, double efficiency = 1.0)
    {
        text_ += "[[lights]]\nname = \"bulb\"\nkind = \"point\"\nposition = " + tomlVec(position) +
            "\npower_w = " + tomlNumber(power_w) + "\nefficiency = " + tomlNumber(efficiency) + "\n";
        return *this;
    }
    /// The camera "cam" at `position` looking at `look_at`.
    SceneText& camera(const std::array<double, 3>& position, const std::array<double, 3>& look_at, int width,
                      int height, double hfov_deg)
    {
        text_ += "[[cameras]]\nname = \"cam\"\nposition = " + tomlVec(position) + "\nlook_at = " + tomlVec(look_at) +
            "\nwidth = " + std::to_string(width) + "\nheight = " + std::to_string(height) +
            "\nhfov_deg = " + tomlNumber(hfov_deg) + "\n";
        return *this;
    }
    /// A box of smoke of `density` on a grid of `voxel` [m], with an inline `medium` table.
    SceneText& boxSmoke(const std::array<double, 3>& lo, const std::array<double, 3>& hi, double density, double voxel,
                        const std::string& medium)
    {
        text_ += "[[smoke]]\nname = \"box\"\ntype = \"box\"\nmin = " + tomlVec(lo) + "\nmax = " + tomlVec(hi) +
            "\nvoxel = " + tomlNumber(voxel) + "\ndensity = " + tomlNumber(density) + "\nmedium = " + medium + "\n";
        return *this;
    }
    /// A .vdb file's grid as smoke, its stored values × `scale` the density.
    SceneText& vdbSmoke(const std::string& file, double scale, const std::string& medium)
    {
        text_ += "[[smoke]]\nname = \"cloud\"\ntype = \"vdb\"\nfile = \"" + file + "\"\nscale = " + tomlNumber(scale) +
            "\nmedium = " + medium + "\n";
        return *this;
    }
    /// A quad surface: `corner` and its edges `u`, `v` [m], of material `material`.
    SceneText& quad(const std::string& name, const std::string& material, const std::array<double, 3>& corner,
                    const std::array<double, 3>& u, const std::array<double, 3>& v)
    {
        text_ += "[[surfaces]]\nname = \"" + name + "\"\nmaterial = \"" + material +
            "\"\ntype = \"quad\"\ncorner = " + tomlVec(corner) + "\nu = " + tomlVec(u) + "\nv = " + tomlVec(v) + "\n";
        return *this;
    }
    /// Anything else, verbatim.
    SceneText& raw(const std::string& toml)
    {
        text_ += toml;
        return *this;
    }
    const std::string& str() const { return text_; }
    operator const std::string&() const { return text_; }

private:
    std::string text_;
};

}  // namespace smokescan::test
