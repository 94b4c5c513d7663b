// What runs before newlib's crt0 (_start: stack, .bss, static constructors, main) on the Cortex-M7:
// the vector table and the reset handler. crt0 expects a loader to have placed .data and leaves
// the FPU off, so both are done here.
#include <cstdint>

extern "C" {
extern std::uint32_t __data_load__, __data_start__, __data_end__, __stack;  // m7.ld
[[noreturn]] void _start();
[[noreturn]] void Reset_Handler();
}

void Reset_Handler() {
  const std::uint32_t* src = &__data_load__;
  for (std::uint32_t* dst = &__data_start__; dst < &__data_end__;) *dst++ = *src++;
  // CPACR: full access to CP10 and CP11 (the FPU) before the first floating-point instruction.
  *reinterpret_cast<volatile std::uint32_t*>(0xE000ED88) |= 0xFu << 20;
  asm volatile("dsb\n\tisb" ::: "memory");
  _start();
}

namespace {

[[noreturn]] void halt() {
  for (;;) {
  }
}

using Vector = void (*)();

}  // namespace

// Initial stack pointer, reset, then the core's fault and system exceptions (NMI .. SysTick), all
// halting in place until the firmware installs its own.
__attribute__((section(".isr_vector"), used)) const Vector g_vectors[16] = {
    reinterpret_cast<Vector>(&__stack), Reset_Handler, halt, halt, halt, halt, halt, nullptr,
    nullptr, nullptr, nullptr, halt, halt, nullptr, halt, halt};
