// ui/convergence.h: the history of the estimated relative MSE of one accumulation, for log-log plots against
// time and spp. ImGui::PlotLines spaces its values evenly, so the curves are resampled on an even log10 grid.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pv::ui {

class ConvergenceHistory {
public:
    // Starts a new accumulation.
    void clear() { m_points.clear(); }
    // Adds the state after a pass; points with rel_mse <= 0 (fewer than 2 spp) are ignored. spp: samples per pixel
    // taken, on average over the image (with adaptive sampling fewer than the passes: the error falls with the
    // samples taken, not with the passes).
    void add(double spp, double seconds, double rel_mse);

    // log10(rel_mse) on `n` evenly spaced log10(x) values from the first to the last point (x = seconds or spp);
    // empty with fewer than two points. lo/hi receive the log10 x range.
    std::vector<float> log_log_by_seconds(int n, float& lo, float& hi) const;
    std::vector<float> log_log_by_spp(int n, float& lo, float& hi) const;
    // Least-squares slope of log10(rel_mse) against log10(spp) over the upper half of the log(spp) range:
    // -1 for an unbiased Monte Carlo estimator; 0 with too few points.
    double slope_vs_spp() const;
    size_t size() const { return m_points.size(); }

private:
    struct Point {
        double log_spp, log_seconds, log_mse;
    };
    std::vector<float> resample(bool by_seconds, int n, float& lo, float& hi) const;
    std::vector<Point> m_points;
};

}  // namespace pv::ui
