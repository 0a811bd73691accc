// A deliberate bug per sanitizer, run by the sanitizer build's tests (tests/CMakeLists.txt):
// each must be reported and abort the program (SIGABRT fails every test, also one that expects
// an error exit), so a broken sanitizer setup cannot pass silently.
#include <climits>
#include <cstdio>
#include <cstring>

namespace {
int* volatile kept = nullptr;  // volatile: the compiler may not reason the bugs away

// In its own frame, so no copy of the pointer stays on main's stack for LeakSanitizer to find.
[[gnu::noinline]] void allocate_and_forget() {
  kept = new int[100];
  kept = nullptr;
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  if (std::strcmp(argv[1], "heap-overflow") == 0) {
    int* p = new int[4]{1, 2, 3, 4};
    kept = p;
    const int x = kept[4];  // one past the end
    delete[] p;
    return x == 12345 ? 3 : 0;
  }
  if (std::strcmp(argv[1], "signed-overflow") == 0) {
    volatile int big = INT_MAX;
    const int x = big + 1;  // undefined behaviour
    return x == 0 ? 3 : 0;
  }
  if (std::strcmp(argv[1], "leak") == 0) {
    allocate_and_forget();  // the only pointer is gone
    return 0;
  }
  if (std::strcmp(argv[1], "clean") == 0) {
    int* p = new int[4]{};
    delete[] p;
    return 0;
  }
  return 2;
}
