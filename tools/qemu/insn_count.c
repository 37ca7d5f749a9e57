/*
 * insn_count: a QEMU TCG plugin (API version 1, qemu-user 7.2) that counts the guest
 * instructions a program executes, exactly, and prints the total when the program exits.
 *
 * How it counts: at translation time every guest instruction of a translation block (TB)
 * gets an inline "counter += 1" (QEMU_PLUGIN_INLINE_ADD_U64, emitted as a TCG op before
 * the instruction, no helper call). The count is therefore the number of guest
 * instructions that started executing. mode=tb instead adds n_insns once per TB entry
 * (faster; exact as long as no TB is left in the middle, which in user mode happens
 * only on a fault). One counter for all vCPUs: meant for single-threaded guests.
 *
 * Build (host):  gcc -O2 -shared -fPIC -fvisibility=hidden -o libinsn_count.so insn_count.c
 * Run:           qemu-ppc -plugin ./libinsn_count.so,outfile=count.txt[,mode=insn|tb][,symbol=SUBSTR][,profile=on][,marker=NAME] prog args
 * Arguments:
 *   outfile=PATH   write "insns N" to PATH (truncated) instead of stderr
 *   mode=insn|tb   per-instruction inline add (default) or per-TB inline add
 *   symbol=SUBSTR  additionally count (mode=insn only) the instructions whose containing
 *                  ELF symbol name contains SUBSTR (mangled C++ names); printed as
 *                  "insns_in_symbol N"
 *   profile=on     additionally count (mode=insn only) per containing ELF symbol; printed
 *                  as "symbol N NAME" lines (mangled), largest first
 *   marker=NAME    every time a translated block that starts in the ELF symbol NAME (an
 *                  unmangled, one-block function such as tests/bench/mapper_probe.cpp's
 *                  vtm_probe_mark) begins to execute, the running total is recorded;
 *                  printed as "mark K N" lines (K = 0, 1, ...), at most 65536. The
 *                  instructions between two marks are exact up to the marker block's own
 *                  few instructions.
 * Output line(s): "insns N" (then "insns_in_symbol N", "symbol N NAME"), decimal.
 * The containing symbol is QEMU's lookup of the guest binary's symbol table (the
 * nearest symbol at or below the address): code inlined into a function counts for
 * that function.
 */
#define _POSIX_C_SOURCE 200809L /* strdup */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "qemu_plugin_api.h"

QEMU_PLUGIN_EXPORT int qemu_plugin_version = QEMU_PLUGIN_VERSION;

static uint64_t insn_total;     /* every executed guest instruction */
static uint64_t insn_in_symbol; /* those inside a symbol matching symbol_filter */
static int per_tb;              /* mode=tb */
static const char *symbol_filter;
static const char *outfile;
static int profile;
static const char *marker;
#define MAX_MARKS 65536u
static uint64_t marks[MAX_MARKS];
static unsigned n_marks;

static void on_marker(unsigned int vcpu_index, void *userdata) {
    (void)vcpu_index;
    (void)userdata;
    if (n_marks < MAX_MARKS) {
        marks[n_marks++] = insn_total;
    }
}

/* Per-symbol counters for profile=on: a fixed open-addressing table filled at
 * translation time (the inline ops need stable counter addresses, so it never moves). */
#define PROFILE_SLOTS 65536u
struct symbol_count {
    const char *name; /* NULL: free slot */
    uint64_t count;
};
static struct symbol_count profile_table[PROFILE_SLOTS];
static unsigned profile_used;

static uint64_t *profile_counter(const char *name) {
    if (name == NULL) {
        name = "(no symbol)";
    }
    unsigned h = 2166136261u;
    for (const char *c = name; *c != '\0'; ++c) {
        h = (h ^ (unsigned char)*c) * 16777619u;
    }
    for (unsigned probe = 0; probe < PROFILE_SLOTS; ++probe) {
        struct symbol_count *e = &profile_table[(h + probe) % PROFILE_SLOTS];
        if (e->name == NULL) {
            if (profile_used + 1 >= PROFILE_SLOTS) {
                break;
            }
            e->name = strdup(name);
            ++profile_used;
            return &e->count;
        }
        if (strcmp(e->name, name) == 0) {
            return &e->count;
        }
    }
    return NULL; /* table full: not profiled (the total still counts) */
}

static int by_count_desc(const void *a, const void *b) {
    const struct symbol_count *x = a;
    const struct symbol_count *y = b;
    return x->count < y->count ? 1 : (x->count > y->count ? -1 : 0);
}

static void on_tb_translated(qemu_plugin_id_t id, struct qemu_plugin_tb *tb) {
    (void)id;
    const size_t n = qemu_plugin_tb_n_insns(tb);
    if (marker != NULL && n > 0) {
        const char *sym = qemu_plugin_insn_symbol(qemu_plugin_tb_get_insn(tb, 0));
        if (sym != NULL && strcmp(sym, marker) == 0) {
            qemu_plugin_register_vcpu_tb_exec_cb(tb, on_marker, QEMU_PLUGIN_CB_NO_REGS, NULL);
        }
    }
    if (per_tb) {
        qemu_plugin_register_vcpu_tb_exec_inline(tb, QEMU_PLUGIN_INLINE_ADD_U64, &insn_total, n);
        return;
    }
    for (size_t i = 0; i < n; ++i) {
        struct qemu_plugin_insn *insn = qemu_plugin_tb_get_insn(tb, i);
        qemu_plugin_register_vcpu_insn_exec_inline(insn, QEMU_PLUGIN_INLINE_ADD_U64, &insn_total, 1);
        if (profile) {
            uint64_t *counter = profile_counter(qemu_plugin_insn_symbol(insn));
            if (counter != NULL) {
                qemu_plugin_register_vcpu_insn_exec_inline(insn, QEMU_PLUGIN_INLINE_ADD_U64, counter, 1);
            }
        }
        if (symbol_filter != NULL) {
            const char *sym = qemu_plugin_insn_symbol(insn);
            if (sym != NULL && strstr(sym, symbol_filter) != NULL) {
                qemu_plugin_register_vcpu_insn_exec_inline(insn, QEMU_PLUGIN_INLINE_ADD_U64,
                                                           &insn_in_symbol, 1);
            }
        }
    }
}

static void report_at_exit(qemu_plugin_id_t id, void *userdata) {
    (void)id;
    (void)userdata;
    char line[128];
    int len = snprintf(line, sizeof line, "insns %llu\n", (unsigned long long)insn_total);
    if (symbol_filter != NULL && len > 0 && (size_t)len < sizeof line) {
        snprintf(line + len, sizeof line - (size_t)len, "insns_in_symbol %llu\n",
                 (unsigned long long)insn_in_symbol);
    }
    FILE *f = outfile != NULL ? fopen(outfile, "w") : NULL;
    if (outfile != NULL && f == NULL) {
        fprintf(stderr, "insn_count: cannot open %s\n", outfile);
    }
    fputs(line, f != NULL ? f : stderr);
    for (unsigned i = 0; i < n_marks; ++i) {
        fprintf(f != NULL ? f : stderr, "mark %u %llu\n", i, (unsigned long long)marks[i]);
    }
    if (profile) {
        qsort(profile_table, PROFILE_SLOTS, sizeof profile_table[0], by_count_desc);
        for (unsigned i = 0; i < PROFILE_SLOTS && profile_table[i].count > 0; ++i) {
            fprintf(f != NULL ? f : stderr, "symbol %llu %s\n",
                    (unsigned long long)profile_table[i].count, profile_table[i].name);
        }
    }
    if (f != NULL) {
        fclose(f);
    }
    qemu_plugin_outs(line); /* also into the -d plugin log */
}

QEMU_PLUGIN_EXPORT int qemu_plugin_install(qemu_plugin_id_t id, const qemu_info_t *info,
                                           int argc, char **argv) {
    if (info->version.cur < QEMU_PLUGIN_VERSION) {
        fprintf(stderr, "insn_count: emulator plugin API %d < %d\n", info->version.cur,
                QEMU_PLUGIN_VERSION);
        return -1;
    }
    for (int i = 0; i < argc; ++i) {
        const char *a = argv[i];
        if (strncmp(a, "outfile=", 8) == 0) {
            outfile = a + 8;
        } else if (strcmp(a, "mode=tb") == 0) {
            per_tb = 1;
        } else if (strcmp(a, "mode=insn") == 0) {
            per_tb = 0;
        } else if (strcmp(a, "profile=on") == 0) {
            profile = 1;
        } else if (strncmp(a, "marker=", 7) == 0) {
            marker = a + 7;
        } else if (strncmp(a, "symbol=", 7) == 0) {
            symbol_filter = a + 7;
        } else {
            fprintf(stderr, "insn_count: unknown argument '%s' (outfile=, mode=insn|tb, symbol=, profile=on, marker=)\n", a);
            return -1;
        }
    }
    if (per_tb && (symbol_filter != NULL || profile)) {
        fprintf(stderr, "insn_count: symbol= and profile=on need mode=insn\n");
        return -1;
    }
    qemu_plugin_register_vcpu_tb_trans_cb(id, on_tb_translated);
    qemu_plugin_register_atexit_cb(id, report_at_exit, NULL);
    return 0;
}
