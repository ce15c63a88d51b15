// app/progress.h: the one progress bar of the CLI (`pathview render` and `pathview bench`), drawn on stderr when
// it is a terminal: "[=====     ]  42%  what", redrawn at most every 0.1 s (and always at 100%).
#pragma once

#include <chrono>
#include <string>

namespace pv::app {

class ProgressBar {
public:
    // Draws nothing unless `enabled` and stderr is a terminal.
    explicit ProgressBar(bool enabled);
    bool enabled() const { return m_enabled; }
    // Redraws the bar at `fraction` (clamped to [0, 1]) with `what` beside it.
    void draw(double fraction, const std::string& what);
    // Leaves the last bar on its line and moves to the next.
    void finish();
    // Erases the bar.
    void clear();

private:
    bool m_enabled;
    std::chrono::steady_clock::time_point m_last{};
};

}  // namespace pv::app
