// Linked into the programs of the sanitizer build only (MOIRE_SANITIZE): dlclose leaves the
// library mapped. LeakSanitizer reports at exit, after the Vulkan loader has closed Mesa's
// drivers (at vkDestroyInstance); a leak inside a library no longer mapped has no module name,
// so no suppression in lsan.supp could match it. Kept mapped, it is named and matched.
int dlclose(void* handle) {
    (void)handle;
    return 0;
}
