// ui/view_log.h: the viewer's --log-file: one line per restart (with its reason), per snapshot and per first
// frame of an accumulation, plus a timing line a second, each prefixed by the seconds since start.
// Written by the UI thread only; every line is flushed so tests can poll the file.
#pragma once

#include <cstdio>
#include <string>

namespace pv::ui {

class ViewLog {
public:
    // An empty path logs nothing. Throws pv::Error when the file cannot be opened.
    explicit ViewLog(const std::string& path);
    ~ViewLog();
    ViewLog(const ViewLog&) = delete;
    ViewLog& operator=(const ViewLog&) = delete;

    // printf-style; a newline is added.
    void line(const char* format, ...) __attribute__((format(printf, 2, 3)));
    double now() const;  // seconds since the log was opened

private:
    std::FILE* m_file = nullptr;
    double m_start = 0.0;
};

}  // namespace pv::ui
