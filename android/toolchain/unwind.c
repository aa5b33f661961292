// The unwinder a panic = "abort" build needs, for the Debian route (Debian ships no LLVM
// libunwind for Android, and Debian's arm64 libunwind is built against glibc). With panics
// aborting, nothing unwinds; std calls these only to capture a backtrace, which is then empty.
// The NDK route links the NDK's real libunwind instead.
#include <stdint.h>

typedef enum { URC_NO_REASON = 0, URC_END_OF_STACK = 5 } unwind_reason;
struct _Unwind_Context;
typedef unwind_reason (*unwind_trace_fn)(struct _Unwind_Context *, void *);

unwind_reason _Unwind_Backtrace(unwind_trace_fn trace, void *arg) {
    (void)trace;
    (void)arg;
    return URC_END_OF_STACK;
}
uintptr_t _Unwind_GetIP(struct _Unwind_Context *c) { (void)c; return 0; }
uintptr_t _Unwind_GetIPInfo(struct _Unwind_Context *c, int *before) {
    (void)c;
    *before = 0;
    return 0;
}
uintptr_t _Unwind_GetCFA(struct _Unwind_Context *c) { (void)c; return 0; }
void *_Unwind_FindEnclosingFunction(void *pc) { (void)pc; return 0; }
