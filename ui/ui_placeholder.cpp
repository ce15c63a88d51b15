// ui/ui_placeholder.cpp: the viewer lands here (issue: interactive previewer).
