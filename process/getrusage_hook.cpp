#include "process/getrusage_hook.h"

#include <elf.h>
#include <link.h>
#include <sys/mman.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>

#include "engine/solvers/ipopt/ipopt_timers.h"

namespace bristle {

int timerAwareGetrusage(int who, struct rusage* usage) noexcept {
  if (usage != nullptr && skipIpoptTimerRead()) {
    std::memset(usage, 0, sizeof *usage);
    return 0;
  }
  return static_cast<int>(syscall(SYS_getrusage, who, usage));
}

namespace {

// The tables of one loaded object's dynamic section that name its relocations.
struct RelocTables {
  const ElfW(Sym)* symtab = nullptr;
  const char* strtab = nullptr;
  const ElfW(Rela)* jmprel = nullptr;  // the PLT's (DT_JMPREL), lazy or not
  std::size_t jmprel_bytes = 0;
  const ElfW(Rela)* rela = nullptr;  // the others (DT_RELA): -fno-plt's GLOB_DAT
  std::size_t rela_bytes = 0;
  std::uintptr_t relro_begin = 0, relro_end = 0;  // pages the loader made read-only
};

// Most loaders relocate the dynamic section's addresses in place (glibc on
// x86-64), some leave them as offsets from the load address: take either.
std::uintptr_t dynAddress(ElfW(Addr) value, ElfW(Addr) base) {
  return value < base ? base + value : value;
}

RelocTables relocTables(const dl_phdr_info& info) {
  RelocTables t;
  const long page = sysconf(_SC_PAGESIZE);
  const ElfW(Dyn)* dyn = nullptr;
  for (int i = 0; i < info.dlpi_phnum; ++i) {
    const ElfW(Phdr)& ph = info.dlpi_phdr[i];
    if (ph.p_type == PT_DYNAMIC)
      dyn = reinterpret_cast<const ElfW(Dyn)*>(info.dlpi_addr + ph.p_vaddr);
    if (ph.p_type == PT_GNU_RELRO && page > 0) {
      // As the loader protects it: whole pages only, its last partial page stays writable.
      const auto mask = ~static_cast<std::uintptr_t>(page - 1);
      t.relro_begin = (info.dlpi_addr + ph.p_vaddr) & mask;
      t.relro_end = (info.dlpi_addr + ph.p_vaddr + ph.p_memsz) & mask;
    }
  }
  if (dyn == nullptr) return t;
  const ElfW(Addr) base = info.dlpi_addr;
  for (; dyn->d_tag != DT_NULL; ++dyn) {
    const ElfW(Addr) v = dyn->d_un.d_ptr;
    switch (dyn->d_tag) {
      case DT_SYMTAB: t.symtab = reinterpret_cast<const ElfW(Sym)*>(dynAddress(v, base)); break;
      case DT_STRTAB: t.strtab = reinterpret_cast<const char*>(dynAddress(v, base)); break;
      case DT_JMPREL: t.jmprel = reinterpret_cast<const ElfW(Rela)*>(dynAddress(v, base)); break;
      case DT_PLTRELSZ: t.jmprel_bytes = dyn->d_un.d_val; break;
      case DT_RELA: t.rela = reinterpret_cast<const ElfW(Rela)*>(dynAddress(v, base)); break;
      case DT_RELASZ: t.rela_bytes = dyn->d_un.d_val; break;
      default: break;
    }
  }
  return t;
}

// Writes `hook` into one slot, opening its page for the write and closing it
// again where the loader had made it read-only (full RELRO, -z now).
bool writeSlot(std::uintptr_t slot, void* hook, const RelocTables& t) {
  const long page = sysconf(_SC_PAGESIZE);
  if (page <= 0 || slot % alignof(void*) != 0) return false;
  void* page_start = reinterpret_cast<void*>(slot & ~static_cast<std::uintptr_t>(page - 1));
  if (mprotect(page_start, static_cast<std::size_t>(page), PROT_READ | PROT_WRITE) != 0)
    return false;
  std::memcpy(reinterpret_cast<void*>(slot), &hook, sizeof hook);
  if (slot >= t.relro_begin && slot < t.relro_end)
    mprotect(page_start, static_cast<std::size_t>(page), PROT_READ);
  return true;
}

// Patches the getrusage relocations among `count` entries: JUMP_SLOT or
// GLOB_DAT (an address slot the code calls through), never another kind.
int patchRelocations(const ElfW(Rela)* rel, std::size_t count, const dl_phdr_info& info,
                     const RelocTables& t, void* hook) {
  int written = 0;
  for (std::size_t i = 0; rel != nullptr && i < count; ++i) {
    const auto type = ELF64_R_TYPE(rel[i].r_info);
    if (type != R_X86_64_JUMP_SLOT && type != R_X86_64_GLOB_DAT) continue;
    const ElfW(Sym)& sym = t.symtab[ELF64_R_SYM(rel[i].r_info)];
    if (std::strcmp(t.strtab + sym.st_name, "getrusage") != 0) continue;
    if (writeSlot(info.dlpi_addr + rel[i].r_offset, hook, t)) ++written;
  }
  return written;
}

struct Patch {
  void* hook;
  int written = 0;
};

int patchObject(dl_phdr_info* info, std::size_t, void* data) {
  const char* name = info->dlpi_name;
  if (name == nullptr || std::strstr(name, "libipopt") == nullptr) return 0;
  const RelocTables t = relocTables(*info);
  if (t.symtab == nullptr || t.strtab == nullptr) return 0;
  auto& patch = *static_cast<Patch*>(data);
  constexpr std::size_t kRela = sizeof(ElfW(Rela));
  patch.written += patchRelocations(t.jmprel, t.jmprel_bytes / kRela, *info, t, patch.hook);
  patch.written += patchRelocations(t.rela, t.rela_bytes / kRela, *info, t, patch.hook);
  return 0;
}

}  // namespace

bool routeIpoptGetrusage(bool through_rule) {
#if defined(__x86_64__) && defined(__linux__)
  int (*target)(int, struct rusage*) noexcept = &timerAwareGetrusage;
  if (!through_rule) target = &::getrusage;
  Patch patch{reinterpret_cast<void*>(target)};
  dl_iterate_phdr(&patchObject, &patch);
  return patch.written > 0;
#else
  static_cast<void>(through_rule);
  return false;  // the relocation kinds above are x86-64's; elsewhere leave Ipopt's timers be
#endif
}

}  // namespace bristle
