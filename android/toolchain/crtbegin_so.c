// What the NDK's crtbegin_so.o gives a shared library, for the Debian route: the library's own
// __dso_handle (Rust's thread-local destructors register against it), the finalizer that runs
// the library's atexit handlers when it is unloaded, and the note that names the API level the
// library was built for.
extern void __cxa_finalize(void *dso);

__attribute__((visibility("hidden"))) void *__dso_handle = &__dso_handle;

__attribute__((destructor, visibility("hidden"))) static void on_dlclose(void) {
    __cxa_finalize(&__dso_handle);
}

// ELF note "Android", type 1 (ABI tag): the API level, as the NDK writes it.
struct android_ident {
    int namesz, descsz, type;
    char name[8];
    int api;
};
__attribute__((section(".note.android.ident"), aligned(4), used))
static const struct android_ident ident = {8, 4, 1, "Android", API_LEVEL};
