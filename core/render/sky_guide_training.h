// core/render/sky_guide_training.h: the sky guide's training pre-pass (docs/sky-guide.md), what it measures for
// `--sky-guide auto`, and the guide's lifecycle in a render (SkyGuideLifecycle, which the Renderer calls). The guide
// itself, what the scene reads, is core/render/sky_guide.h.
#pragma once

#include <memory>
#include <string>

#include "core/render/integrator.h"
#include "core/render/sky_guide.h"
#include "core/render/traceable_scene.h"
#include "core/scene/camera.h"

// PathWalker (core/render/integrator.h), watching each vertex that takes a light sample (a PathObserver): there it
// sends shadow rays toward sky directions drawn from the sky's own distribution and accumulates, per direction bin
// and cell, the sky light that actually arrives (luminance of beta f |cos| Le V / pdf).

namespace pv {

// Cells of the training pre-pass's grids over the film (two paths each): a pilot of one path per pixel (between
// kSkyGuidePilotCells and kSkyGuideMaxPilotCells cells: the viewer's coarse passes after every camera move pay it)
// decides, then where the guide is used more paths make kSkyGuideTrainingCells in all.
constexpr int kSkyGuideTrainingCells = 128 * 128;
constexpr int kSkyGuidePilotCells = 2048;
constexpr int kSkyGuideMaxPilotCells = 8192;
// Spatial cells of the guide (about; cubic over the scene's bounds, 1 to 16 per axis).
constexpr int kSkyGuideCells = 64;

// True when the guide would change anything: the switch is on, next-event estimation is on, the sky shines and the
// scene declares no portals (portals already aim the sky's samples at the openings).
bool sky_guide_applies(const TraceableScene& ts, const RenderSettings& settings);

// The training pre-pass and what it measured for `--sky-guide auto` (docs/sky-guide.md): the guide would cut the
// variance of the pixel estimate by `variance_ratio` = 1 - saved / noise, where noise is the variance of the
// training paths' NEE-only estimates (from the two paths of each training cell) and saved the second moment the
// guide's mixture would take out of their sky samples (importance reweighting, each path's samples judged by the
// guide trained on the other paths). Auto uses the guide where variance_ratio x kSkyGuideRelativeCost < 1.
struct SkyGuideTraining {
    std::shared_ptr<const SkyGuide> guide;  // nullptr: learned nothing
    bool use = false;                       // auto's decision
    double variance_ratio = 1.0;
    double sky_share = 0.0;  // of the NEE-only estimate, from the sky
    double sun_share = 0.0;  // of the environment's part of it, from the sun
};
// Time per sample with the guide over without (measured 1.14-1.30 on the five scenes of docs/sky-guide.md).
constexpr double kSkyGuideRelativeCost = 1.25;

SkyGuideTraining train_sky_guide_judged(const TraceableScene& ts, const RenderSettings& settings, const Camera& camera);

// The training pre-pass: camera paths through `camera` (the render's; its film is sampled on a coarse grid in the
// same aspect) with a seed of its own derived from settings.seed. Deterministic for any thread count (fixed chunks,
// one histogram each, summed in chunk order). Runs on the calling thread's TBB arena. Nothing (nullptr) when the
// guide does not apply or learned nothing.
std::shared_ptr<const SkyGuide> train_sky_guide(const TraceableScene& ts, const RenderSettings& settings,
                                                const Camera& camera);

// The guide in a render's accumulations: trained in the first pass after a restart (timed with it) and frozen for
// the accumulation, so every shard, resume and half buffer sees the same one; with keep (the viewer), a restart that
// changes only the camera or the image size keeps it and auto's decision. New settings or a new scene version
// (materials, environment) retrain.
class SkyGuideLifecycle {
public:
    void set_keep(bool keep) { m_keep = keep; }
    // At a restart with `settings` on the scene's `version`: keeps the guide, or clears the scene's and trains in
    // the next pass.
    void restart(TraceableScene& ts, const RenderSettings& settings, uint64_t version);
    // At the start of a pass: trains when due (on the calling thread's TBB arena) and gives the scene the guide
    // (with auto, only where it pays). Nothing otherwise.
    void train_if_due(TraceableScene& ts, const RenderSettings& settings, const Camera& camera);
    bool due() const { return m_due; }
    double seconds() const { return m_seconds; }  // the last training's (0: none trained since the restart)
    bool used() const { return m_used; }          // the trained guide samples the sky
    double variance_ratio() const { return m_variance_ratio; }
    // The settings with sky_guide on only where the guide applies and, for auto, once decided, where it is used.
    RenderSettings as_rendered(const TraceableScene& ts, const RenderSettings& settings) const;
    // "" with --sky-guide off, else "not applicable", "training in the first pass", or "on" / "off" (with auto's
    // predicted variance ratio).
    std::string status(const TraceableScene& ts, const RenderSettings& settings) const;

private:
    bool m_keep = false;
    bool m_due = false;      // train in the next pass
    bool m_decided = false;  // trained (so not due) for m_settings on m_version
    RenderSettings m_settings;
    uint64_t m_version = 0, m_pending_version = 0;
    double m_seconds = 0.0;
    bool m_used = false;
    double m_variance_ratio = 1.0;
};

}  // namespace pv
