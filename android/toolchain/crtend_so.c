// The NDK's crtend_so.o closes what crtbegin_so.o opened; on arm64 nothing is left to close.
// Linked so the link line is the one rustc gives (crtbegin_so.o ... crtend_so.o).
