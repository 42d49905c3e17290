/* image/image_module.c -- loading a plug-in module safely (image_module_open, image/image.h): the checks the
 * codec module (image/image_codec.c) and the program's window module (cli/view) get before dlopen runs any of
 * the file's code.  Apart from image_codec.c so that builds with another codec (the valgrind stage's
 * tests/valgrind/codec_raw.c) have it too. */
#define _GNU_SOURCE  /* RTLD_* */
#include "image_internal.h"

#include <dlfcn.h>
#include <elf.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* image_dir_of: see image_internal.h. */
void image_dir_of(const char *path, char *dir, size_t len)
{
    const char *slash = strrchr(path, '/');
    if (!slash) snprintf(dir, len, ".");
    else snprintf(dir, len, "%.*s", (int)(slash - path), path);
}

/* Whether st (the module or its folder, named path) may hold code this process runs: owned by root or by this
 * user, and not writable by others (a world-writable folder only with the sticky bit, as /tmp); else false
 * with the reason in err. */
static bool trusted(const char *path, const struct stat *st, bool folder, char *err, size_t errlen)
{
    uid_t me = geteuid();
    const char *what = folder ? "folder of the module" : "module";
    if (st->st_uid != 0 && st->st_uid != me) {
        image_set_err(err, errlen, "%s: the %s is owned by user %u, neither root nor this user (%u): refused", path,
                      what, (unsigned)st->st_uid, (unsigned)me);
        return false;
    }
    if ((st->st_mode & S_IWOTH) && !(folder && (st->st_mode & S_ISVTX))) {
        image_set_err(err, errlen, "%s: the %s is writable by every user: refused", path, what);
        return false;
    }
    return true;
}

/* Whether the symbol table section ds (string table ss) of the ELF file fd (size bytes) defines name. */
static bool dynsym_defines(int fd, uint64_t size, const Elf64_Shdr *ds, const Elf64_Shdr *ss, const char *name)
{
    if (ds->sh_offset > size || ds->sh_size > size - ds->sh_offset || ss->sh_offset > size ||
        ss->sh_size > size - ss->sh_offset || ss->sh_size == 0)
        return false;
    bool found = false;
    Elf64_Sym *sym = malloc(ds->sh_size ? ds->sh_size : 1);
    char *str = malloc(ss->sh_size + 1);
    if (sym && str && pread(fd, sym, ds->sh_size, (off_t)ds->sh_offset) == (ssize_t)ds->sh_size &&
        pread(fd, str, ss->sh_size, (off_t)ss->sh_offset) == (ssize_t)ss->sh_size) {
        str[ss->sh_size] = 0;
        for (size_t i = 0; i < ds->sh_size / sizeof *sym && !found; i++)
            found = sym[i].st_shndx != SHN_UNDEF && sym[i].st_name < ss->sh_size && !strcmp(str + sym[i].st_name, name);
    }
    free(sym);
    free(str);
    return found;
}

/* Whether the ELF file at fd (size bytes) defines the dynamic symbol `name` (its .dynsym section, every offset
 * checked against the file); false with the reason in err naming path.  Read before dlopen, so that a file that
 * is not the module it is named after never runs a constructor. */
static bool elf_defines(int fd, uint64_t size, const char *name, const char *path, char *err, size_t errlen)
{
    Elf64_Ehdr eh;
    if (pread(fd, &eh, sizeof eh, 0) != (ssize_t)sizeof eh || memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0 ||
        eh.e_ident[EI_CLASS] != ELFCLASS64 || eh.e_type != ET_DYN || eh.e_shentsize != sizeof(Elf64_Shdr) ||
        eh.e_shnum == 0 || eh.e_shoff > size || (uint64_t)eh.e_shnum * sizeof(Elf64_Shdr) > size - eh.e_shoff) {
        image_set_err(err, errlen, "%s: not a 64-bit ELF shared object: refused (not loaded)", path);
        return false;
    }
    bool found = false;
    size_t shbytes = (size_t)eh.e_shnum * sizeof(Elf64_Shdr);
    Elf64_Shdr *sh = malloc(shbytes);
    if (sh && pread(fd, sh, shbytes, (off_t)eh.e_shoff) == (ssize_t)shbytes)
        for (unsigned k = 0; k < eh.e_shnum && !found; k++)
            found = sh[k].sh_type == SHT_DYNSYM && sh[k].sh_link < eh.e_shnum &&
                    sh[k].sh_entsize == sizeof(Elf64_Sym) && dynsym_defines(fd, size, &sh[k], &sh[sh[k].sh_link], name);
    free(sh);
    if (!found)
        image_set_err(err, errlen, "%s: does not define %s, so it is not the module it is named after: refused (not "
                      "loaded)", path, name);
    return found;
}

/* dlopen the module at path (absolute) after checking it: a regular file, it and its folder trusted, an ELF
 * shared object defining `symbol`; the handle, or NULL with the reason in err. */
static void *module_open_checked(const char *path, const char *symbol, char *err, size_t errlen)
{
    char real[PATH_MAX], folder[PATH_MAX];
    struct stat st;
    if (!realpath(path, real) || stat(real, &st) != 0)
        return image_set_err(err, errlen, "%s: %s", path, strerror(errno)), NULL;
    if (!S_ISREG(st.st_mode)) return image_set_err(err, errlen, "%s: not a regular file: refused", path), NULL;
    if (!trusted(real, &st, false, err, errlen)) return NULL;
    image_dir_of(real, folder, sizeof folder);
    if (stat(folder, &st) != 0) return image_set_err(err, errlen, "%s: %s", folder, strerror(errno)), NULL;
    if (!trusted(folder, &st, true, err, errlen)) return NULL;
    int fd = open(real, O_RDONLY | O_CLOEXEC);
    if (fd < 0) return image_set_err(err, errlen, "%s: %s", path, strerror(errno)), NULL;
    bool ok = fstat(fd, &st) == 0 && S_ISREG(st.st_mode) &&
              elf_defines(fd, (uint64_t)st.st_size, symbol, path, err, errlen);
    close(fd);
    if (!ok) return NULL;
    dlerror();
    void *h = dlopen(real, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        const char *why = dlerror();
        image_set_err(err, errlen, "%s: cannot be loaded: %s", path, why ? why : "unknown reason");
    }
    return h;
}

void *image_module_open(const char *path, const char *symbol, char *err, size_t errlen)
{
    if (!path || !symbol || !*symbol) return image_set_err(err, errlen, "image_module_open: no path or symbol"), NULL;
    if (path[0] != '/')
        return image_set_err(err, errlen, "%.300s: not an absolute path: refused (a module is never loaded from the "
                             "current directory)", path), NULL;
    return module_open_checked(path, symbol, err, errlen);
}
