// core/base/tsan.h: ThreadSanitizer happens-before annotations for fork/join through oneTBB. Debian's libtbb is not
// built with -fsanitize=thread, so TSan cannot see that a parallel_for's tasks start after the code before the
// loop and finish before the code after it; these annotations state exactly those two edges and nothing more
// (tests/tsan.supp documents what else is suppressed). No-ops unless compiled with -fsanitize=thread.
#pragma once

#if defined(__SANITIZE_THREAD__)
#define PV_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define PV_TSAN 1
#endif
#endif

#ifdef PV_TSAN
extern "C" void __tsan_acquire(void* addr);
extern "C" void __tsan_release(void* addr);
#endif

namespace pv {

inline void tsan_acquire(const void* edge) {
#ifdef PV_TSAN
    __tsan_acquire(const_cast<void*>(edge));
#else
    (void)edge;
#endif
}
inline void tsan_release(const void* edge) {
#ifdef PV_TSAN
    __tsan_release(const_cast<void*>(edge));
#else
    (void)edge;
#endif
}

// Inside a parallel task: acquires the fork edge on entry and releases the join edge on every exit.
class TsanTaskScope {
public:
    TsanTaskScope(const void* fork, const void* join) : m_join(join) { tsan_acquire(fork); }
    ~TsanTaskScope() { tsan_release(m_join); }
    TsanTaskScope(const TsanTaskScope&) = delete;
    TsanTaskScope& operator=(const TsanTaskScope&) = delete;

private:
    const void* m_join;
};

}  // namespace pv
