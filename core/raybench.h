// core/raybench.h: Embree's raw ray rate through pv::Accel (in progress).
#pragma once
