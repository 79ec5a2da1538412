// `smokescan volume info|build|export` and `smokescan scene list|show`.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/io/run_files.hpp"
#include "smokescan/scene/scene_io.hpp"

namespace smokescan::cli {
namespace {

struct VolumeArgs {
    std::string input, out, grid = "density";
    double time_s = 0, scale = 1.0;
};

bool isVdb(const std::string& p) { return std::filesystem::path(p).extension() == ".vdb"; }

void printInfo(const std::string& label, const GridInfo& i, double scale)
{
    say("%s\n", label.c_str());
    say("  grid '%s' (stored as %s), voxel %.6g m", i.name.c_str(), i.source_type.c_str(), i.voxel_size_m);
    if (scale >= 0) say(", timeline scale %.6g at this time", scale);
    say("\n");
    say("  %lld active voxels in %lld leaves, %lld active tiles, %.1f MB\n", i.active_voxels, i.leaf_nodes,
        i.active_tiles, i.memory_bytes / 1e6);
    if (i.world_bounds.empty()) {
        say("  empty (no non-zero density)\n");
        return;
    }
    say("  index support [%d,%d,%d] -> [%d,%d,%d]\n", i.index_min[0], i.index_min[1], i.index_min[2], i.index_max[0],
        i.index_max[1], i.index_max[2]);
    say("  world bounds [%.4g, %.4g, %.4g] -> [%.4g, %.4g, %.4g] m\n", i.world_bounds.lo.x(), i.world_bounds.lo.y(),
        i.world_bounds.lo.z(), i.world_bounds.hi.x(), i.world_bounds.hi.y(), i.world_bounds.hi.z());
    say("  density %.6g … %.6g\n", i.min_value, i.max_value);
}

int runInfo(const VolumeArgs& a)
{
    if (isVdb(a.input)) {
        VdbLoadConfig c;
        c.grid_name = a.grid;
        c.scale = a.scale;
        printInfo(a.input, DensityGrid::loadVdb(a.input, c).info(), -1.0);
        return 0;
    }
    const Scene scene = loadScene(a.input);
    say("%s: %zu smoke volumes at t = %g s\n", scene.source.c_str(), scene.volumes.size(), a.time_s);
    for (const auto& v : scene.volumes)
        printInfo(v.name + (v.role == SmokeRole::Regional ? " (regional, " : " (local, ") + v.medium.name + ")",
                  v.gridAt(a.time_s)->info(), v.timeline.at(a.time_s));
    return 0;
}

int runBuild(const VolumeArgs& a)
{
    const Scene scene = loadScene(a.input);
    RunFiles files;
    recordSceneInputs(files, a.input, scene);
    files.output(a.out, "--out");
    if (scene.volumes.empty()) throw Error(scene.source, "has no smoke volumes to build");
    std::vector<std::pair<std::string, DensityGrid>> grids;
    for (const auto& v : scene.volumes) grids.emplace_back(v.name, v.gridAt(a.time_s)->scaled(v.timeline.at(a.time_s)));
    DensityGrid::writeVdb(files.stage(a.out), grids);
    files.commit();
    say("wrote %s: %zu grids (density at t = %g s)\n", a.out.c_str(), grids.size(), a.time_s);
    return 0;
}

int runExport(const VolumeArgs& a)
{
    VdbLoadConfig c;
    c.grid_name = a.grid;
    c.scale = a.scale;
    RunFiles files;
    files.input(a.input, "the input");
    files.output(a.out, "--out");
    const DensityGrid g = DensityGrid::loadVdb(a.input, c);
    DensityGrid::writeVdb(files.stage(a.out), {{"density", g}});
    files.commit();
    say("wrote %s: float grid 'density' (stored values × %g)\n", a.out.c_str(), a.scale);
    return 0;
}

}  // namespace

void addVolume(CLI::App& app, Runner& run)
{
    auto a = std::make_shared<VolumeArgs>();
    auto* v = app.add_subcommand("volume", "Inspect, build and write smoke grids (OpenVDB)");
    v->require_subcommand(1);
    auto* info = v->add_subcommand("info", "Describe a .vdb file's grid, or a scene's smoke volumes at a time");
    info->add_option("input", a->input, "A .vdb file, a scene file or a built-in scene")->required();
    info->add_option("--grid", a->grid, "Grid name in a .vdb file (\"\" = first scalar grid)")->capture_default_str();
    info->add_option("--scale", a->scale, "Stored value × scale = density, in (0, 1e6]")
        ->capture_default_str()
        ->check(positive())
        ->check(range(0, 1e6));
    info->add_option("--time", a->time_s, "Scene time [s]")->capture_default_str()->check(finite());
    info->callback([a, &run] { run = [a] { return runInfo(*a); }; });

    auto* build = v->add_subcommand("build", "Voxelise a scene's smoke at a time and write every volume as a grid");
    build->add_option("scene", a->input, "Scene file or built-in scene")->required();
    build->add_option("--time", a->time_s, "Scene time [s]")->capture_default_str()->check(finite());
    build->add_option("--out", a->out, "Output .vdb")->required();
    build->callback([a, &run] { run = [a] { return runBuild(*a); }; });

    auto* exp =
        v->add_subcommand("export", "Read a grid made elsewhere, validate it, write it as a float density grid");
    exp->add_option("input", a->input, "Input .vdb")->required();
    exp->add_option("--grid", a->grid, "Grid name (\"\" = first scalar grid)")->capture_default_str();
    exp->add_option("--scale", a->scale, "Stored value × scale = density, in (0, 1e6]")
        ->capture_default_str()
        ->check(positive())
        ->check(range(0, 1e6));
    exp->add_option("--out", a->out, "Output .vdb")->required();
    exp->callback([a, &run] { run = [a] { return runExport(*a); }; });
}

void addScene(CLI::App& app, Runner& run)
{
    auto name = std::make_shared<std::string>();
    auto* s = app.add_subcommand("scene", "Built-in scenes");
    s->require_subcommand(1);
    auto* list = s->add_subcommand("list", "List built-in scenes");
    list->callback([&run] {
        run = [] {
            for (const auto& n : builtinSceneNames()) say("%s\n", n.c_str());
            return 0;
        };
    });
    auto* show = s->add_subcommand("show", "Print a built-in scene's TOML (a starting point for your own)");
    show->add_option("name", *name, "Built-in scene")->required();
    show->callback([name, &run] {
        run = [name] {
            std::cout << builtinSceneText(*name);
            return 0;
        };
    });
}

}  // namespace smokescan::cli
