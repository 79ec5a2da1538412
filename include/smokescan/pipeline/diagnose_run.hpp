#pragma once
/// @file diagnose_run.hpp
/// @brief `smokescan diagnose` as one library call: a recorded run replayed through the
/// simulation, what it gets wrong, the cause, the extended model and its held-out gain
/// (docs/diagnosis.md); its files written by a second call.
///
/// | field       | default              | meaning                                                     |
/// |-------------|----------------------|-------------------------------------------------------------|
/// | in          | FitInputsConfig's    | the recorded run: log or bag, saturation, calibration, scene, sensor (fit/fit_inputs.hpp) |
/// | sensor_file | ""                   | the model diagnosed ("": the scene's sensor; the omnicam needs its onset file) |
/// | model       | none                 | a laser's paper or physical model (none: the scene's or the sensor file's) |
/// | replay      | ReplayConfig's, offset_s NaN | the replay (diagnose/replay.hpp); offset_s NaN: the sensor file's clock_offset_s |
/// | diag        | DiagnosisConfig's    | level, rounds, seed (diagnose/diagnosis.hpp); its progress is called too |
/// | omni        | OmniFitConfig's      | the omnicam's classes; those named in omni_given must match its sensor file's |
/// | on_scene    | none                 | called with the scene once it is read, before any work (a caller protecting its files) |
#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>

#include "smokescan/diagnose/diagnosis.hpp"
#include "smokescan/diagnose/diagnosis_report.hpp"
#include "smokescan/diagnose/replay.hpp"
#include "smokescan/fit/fit_inputs.hpp"
#include "smokescan/fit/omni_fit.hpp"
#include "smokescan/pipeline/run_control.hpp"
#include "smokescan/sensor_config/sensor_file.hpp"

namespace smokescan {

class AtomicFolder;

struct DiagnoseRunConfig {
    FitInputsConfig in;
    std::string sensor_file;
    std::optional<SensorModel> model;
    ReplayConfig replay = [] {
        ReplayConfig r;
        r.offset_s = NAN;
        return r;
    }();
    DiagnosisConfig diag;
    OmniFitConfig omni;
    std::set<std::string> omni_given;  ///< "--tolerance", "--max-range", "--floor-z" when given
    std::function<void(const Scene&)> on_scene;
};

struct DiagnoseRunResult {
    DiagnosisResult diagnosis;
    DiagnosisSources sources;  ///< what the report names as the run's inputs
    std::unique_ptr<Scene> scene;  ///< the scene read (its files are the run's inputs)
    std::unique_ptr<Replay> replay;
    /// The extended model as a sensor file: a laser's, or the omnicam's onset file.
    std::optional<SensorConfig> laser;
    std::optional<OmniSensorFile> omni;
    std::string sensor_comment;  ///< the sensor file's header comment
};

/// @brief Reads the run's files, replays it and diagnoses it. With a control, the work runs on
/// another thread while the calling thread reports progress (each round's candidates: done,
/// total) and asks cancel about every 50 ms; a cancel stops the replay within a beam's or a scan
/// time's work and the diagnosis after its current candidate. on_scene and diag.progress are
/// called on the thread doing the work.
/// @throw Error naming the file or option at fault; Cancelled
DiagnoseRunResult runDiagnosis(DiagnoseRunConfig cfg, const RunControl& control = {});

/// @brief The diagnosis's JSON report (diagnosis.json's text; docs/diagnosis.md).
std::string diagnosisReportJson(const DiagnoseRunResult& r);

/// @brief diagnosis.json, report.md (with its plots) and sensor.toml into `out`, then commits it.
void writeDiagnosisFolder(AtomicFolder& out, const DiagnoseRunResult& r);

}  // namespace smokescan
