/*
 * Minimal declarations of the QEMU TCG plugin API, version 1 (QEMU 6.0 .. 8.1; here:
 * Debian 12's qemu-user 7.2), for tools/qemu/insn_count.c.
 *
 * Why this file exists: Debian's qemu-user is built with plugin support (the qemu-*
 * binaries export qemu_plugin_* symbols and accept -plugin) but no package ships the
 * header include/qemu/qemu-plugin.h. These are only the declarations insn_count.c
 * uses, written from the public API documentation (qemu docs/devel/tcg-plugins.rst,
 * "API" section of the 7.2 manual); types, enum values and argument orders checked
 * against QEMU 7.2's include/qemu/qemu-plugin.h. The plugin is loaded by dlopen() into
 * the emulator and calls these functions, which the emulator exports; nothing here is
 * linked against QEMU at build time.
 *
 * Version rules (plugins/loader.c, 7.2): a plugin must export `int qemu_plugin_version`
 * with QEMU_PLUGIN_MIN_VERSION (0) <= value <= QEMU_PLUGIN_VERSION (1), and
 * `qemu_plugin_install`. Version 2 (QEMU 8.2+) removed the *_exec_inline functions used
 * here in favour of *_exec_inline_per_vcpu; this file is for version 1 only.
 */
#ifndef VTM_QEMU_PLUGIN_API_H
#define VTM_QEMU_PLUGIN_API_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define QEMU_PLUGIN_EXPORT __attribute__((visibility("default")))
#define QEMU_PLUGIN_VERSION 1

/* Opaque plugin id handed to qemu_plugin_install(). */
typedef uint64_t qemu_plugin_id_t;

/* The API level the plugin was built against (checked by the loader). */
extern QEMU_PLUGIN_EXPORT int qemu_plugin_version;

/* What the emulator tells the plugin at install time (valid during the call only). */
typedef struct qemu_info_t {
    const char *target_name; /* guest architecture, e.g. "ppc" */
    struct {
        int min; /* oldest API version the emulator accepts */
        int cur; /* API version of the emulator */
    } version;
    bool system_emulation; /* false for qemu-user (linux-user) */
    union {
        struct {
            int smp_vcpus;
            int max_vcpus;
        } system; /* only meaningful when system_emulation */
    };
} qemu_info_t;

/* Called once when the plugin is loaded; 0 = success. argv holds "key=value" strings
 * from -plugin file=...,key=value,... and stays valid for the plugin's lifetime. */
QEMU_PLUGIN_EXPORT int qemu_plugin_install(qemu_plugin_id_t id, const qemu_info_t *info,
                                           int argc, char **argv);

struct qemu_plugin_tb;   /* a translation block, valid in the translation callback */
struct qemu_plugin_insn; /* one guest instruction of such a block */

typedef void (*qemu_plugin_udata_cb_t)(qemu_plugin_id_t id, void *userdata);
typedef void (*qemu_plugin_vcpu_tb_trans_cb_t)(qemu_plugin_id_t id, struct qemu_plugin_tb *tb);

/* Inline operations: emitted as TCG ops in the translated code, no helper call. */
enum qemu_plugin_op {
    QEMU_PLUGIN_INLINE_ADD_U64, /* *(uint64_t *)ptr += imm */
};

void qemu_plugin_register_vcpu_tb_trans_cb(qemu_plugin_id_t id, qemu_plugin_vcpu_tb_trans_cb_t cb);

/* A helper call when a translated block starts executing (marker=). */
enum qemu_plugin_cb_flags {
    QEMU_PLUGIN_CB_NO_REGS, /* the callback does not access the guest registers */
    QEMU_PLUGIN_CB_R_REGS,
    QEMU_PLUGIN_CB_RW_REGS,
};
typedef void (*qemu_plugin_vcpu_udata_cb_t)(unsigned int vcpu_index, void *userdata);
void qemu_plugin_register_vcpu_tb_exec_cb(struct qemu_plugin_tb *tb, qemu_plugin_vcpu_udata_cb_t cb,
                                          enum qemu_plugin_cb_flags flags, void *userdata);
void qemu_plugin_register_vcpu_tb_exec_inline(struct qemu_plugin_tb *tb, enum qemu_plugin_op op,
                                              void *ptr, uint64_t imm);
void qemu_plugin_register_vcpu_insn_exec_inline(struct qemu_plugin_insn *insn,
                                                enum qemu_plugin_op op, void *ptr, uint64_t imm);
size_t qemu_plugin_tb_n_insns(const struct qemu_plugin_tb *tb);
uint64_t qemu_plugin_tb_vaddr(const struct qemu_plugin_tb *tb);
struct qemu_plugin_insn *qemu_plugin_tb_get_insn(const struct qemu_plugin_tb *tb, size_t idx);
uint64_t qemu_plugin_insn_vaddr(const struct qemu_plugin_insn *insn);
/* Name of the ELF symbol containing the instruction, or NULL (user mode: from the
 * guest binary's symbol table). */
const char *qemu_plugin_insn_symbol(const struct qemu_plugin_insn *insn);
void qemu_plugin_register_atexit_cb(qemu_plugin_id_t id, qemu_plugin_udata_cb_t cb, void *userdata);
/* Writes to the emulator's log; visible only with -d plugin (and -D file). */
void qemu_plugin_outs(const char *string);

#endif /* VTM_QEMU_PLUGIN_API_H */
