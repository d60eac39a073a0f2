"""Generate the C message tables of the firmware frame layer from the DBC.

    python -m hil.bus.cgen DBC OUTDIR

writes OUTDIR/fcc_bus_msgs.h and OUTDIR/fcc_bus_msgs.c: one physical struct per
message (reals as fcc_real_t, integers as integers, flags as bool), the union of
them, and the descriptor tables (fcc_bus_desc.h) that fcc_bus.c walks.  It sits
beside the codec cantools generates into the same directory (fcc_hil.h/.c,
raw structs and bit packing), which the tables call.  Run it through dbc/generate.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from cantools.database.can.c_source import camel_to_snake_case

from hil.bus import dbc

HEADER = "fcc_bus_msgs.h"
SOURCE = "fcc_bus_msgs.c"
BANNER = """/*
 * {name} -- GENERATED from {dbc} by `python -m hil.bus.cgen` (run dbc/generate).
 * Do not edit: change the DBC and regenerate.  tests/python/bus/test_bus_codegen.py
 * fails when this file and the DBC disagree.
 */
"""


def _snake(name: str) -> str:
    return camel_to_snake_case(name)


def _raw_type(sig: dbc.SignalSpec) -> str:
    for bits in (8, 16, 32, 64):
        if sig.length <= bits:
            return f"{'I' if sig.signed else 'U'}{bits}"
    raise ValueError(sig.name)


def _phys_type(sig: dbc.SignalSpec) -> str:
    if not sig.is_integer:
        return "REAL"
    if sig.length == 1 and not sig.signed:
        return "BOOL"
    return _raw_type(sig)


C_TYPES = {"U8": "uint8_t", "U16": "uint16_t", "U32": "uint32_t", "U64": "uint64_t",
           "I8": "int8_t", "I16": "int16_t", "I32": "int32_t", "I64": "int64_t",
           "BOOL": "bool", "REAL": "fcc_real_t"}


def _c_comment(text: str | None) -> str:
    return (text or "").replace("*/", "* /").replace("\n", " ").strip()


def _fmt_real(x: float) -> str:
    return f"{x:.10g}"


def _field_doc(sig: dbc.SignalSpec, raw_comment: str | None) -> str:
    unit = f" {sig.unit}" if sig.unit else ""
    if sig.is_integer:
        rng = f"[{sig.raw_min}, {sig.raw_max}]{unit}"
    else:
        rng = (f"[{_fmt_real(sig.raw_min / sig.inv_scale)}, {_fmt_real(sig.raw_max / sig.inv_scale)}]"
               f"{unit}, LSB {_fmt_real(1.0 / sig.inv_scale)}")
    comment = _c_comment(raw_comment)
    return f"{rng}. {comment}" if comment else rng


class _Names:
    def __init__(self, db_name: str, msg: dbc.MessageSpec) -> None:
        self.snake = _snake(msg.name)
        self.enum = f"FCC_MSG_{msg.name.upper()}"
        self.phys = f"fcc_msg_{self.snake}_t"
        self.raw = f"struct {db_name}_{self.snake}_t"
        self.pack = f"{db_name}_{self.snake}_pack"
        self.unpack = f"{db_name}_{self.snake}_unpack"


def _node_mask(nodes: tuple[str, ...], names: tuple[str, ...]) -> str:
    bits = [f"(1u << FCC_BUS_NODE_{n})" for n in names if n in nodes]
    return " | ".join(bits) if bits else "0u"


def _app_macro(app: str) -> str:
    return f"FCC_BUS_APP_{app.upper()}"


def _check_apps(spec: dbc.BusSpec) -> None:
    """The application ids are SIM_TICK.app's values: as many applications as values."""
    ticks = spec.by_name("SIM_TICK").signal("app").choices
    if len(ticks) != len(spec.apps):
        raise ValueError(f"{dbc.APP_ATTRIBUTE} names {len(spec.apps)} applications, "
                         f"SIM_TICK.app's value table {len(ticks)}")


def _app_header(spec: dbc.BusSpec) -> list[str]:
    out = [f"/* fcc's applications ({dbc.APP_ATTRIBUTE}; the ids are SIM_TICK.app's values) and each",
           " * one's inputs: the frames sent to FCC with its FccApp, in identifier order (its input",
           " * slots).  fcc_bus_input_app[]: the application whose input a message is, else FCC_BUS_NO_APP. */"]
    for i, app in enumerate(spec.apps):
        out.append(f"#define {_app_macro(app)} {i}u")
    out.append(f"#define FCC_BUS_N_APPS {len(spec.apps)}u")
    out.append("#define FCC_BUS_NO_APP FCC_BUS_N_APPS")
    for app in spec.apps:
        out.append(f"#define {_app_macro(app)}_N_INPUTS {len(spec.app_inputs(app))}u")
    widest = max((len(spec.app_inputs(app)) for app in spec.apps), default=0)
    out.append(f"#define FCC_BUS_MAX_APP_INPUTS {max(widest, 1)}u /* at least 1: an array's size */")
    for app in spec.apps:   # (an application without inputs has no table: C has no empty array)
        if spec.app_inputs(app):
            out.append(f"extern const fcc_msg_t fcc_bus_app_{app}_inputs[{_app_macro(app)}_N_INPUTS];")
    out.append("extern const uint8_t fcc_bus_input_app[FCC_MSG_COUNT];\n")
    return out


def _app_source(spec: dbc.BusSpec, db_name: str) -> list[str]:
    out = []
    for app in (a for a in spec.apps if spec.app_inputs(a)):
        names = ", ".join(_Names(db_name, m).enum for m in spec.app_inputs(app))
        out.append(f"const fcc_msg_t fcc_bus_app_{app}_inputs[{_app_macro(app)}_N_INPUTS] = "
                   f"{{{names}}};\n")
    inputs = {m.name: app for app in spec.apps for m in spec.app_inputs(app)}
    out.append("const uint8_t fcc_bus_input_app[FCC_MSG_COUNT] = {")
    for m in spec.messages:
        app = _app_macro(inputs[m.name]) if m.name in inputs else "FCC_BUS_NO_APP"
        out.append(f"    (uint8_t){app}, /* {m.name} */")
    out.append("};\n")
    return out


def generate_header(spec: dbc.BusSpec, db_name: str) -> str:
    out = [BANNER.format(name=HEADER, dbc=f"dbc/{spec.path.name}"),
           "#ifndef FCC_BUS_MSGS_H\n#define FCC_BUS_MSGS_H\n",
           "#include <stdbool.h>\n#include <stdint.h>\n",
           f'#include "fcc_bus_desc.h"\n#include "{db_name}.h"\n#include "fcc_types.h"\n',
           "/* Nodes: bit positions in fcc_bus_msg_desc_t.senders and .receivers. */"]
    for i, node in enumerate(spec.nodes):
        out.append(f"#define FCC_BUS_NODE_{node} {i}u")
    out.append(f"#define FCC_BUS_N_NODES {len(spec.nodes)}u\n")
    out.append("/* Messages: index in fcc_bus_msg_table[] (sorted by CAN identifier). */")
    out.append("typedef enum {")
    for i, m in enumerate(spec.messages):
        out.append(f"    {_Names(db_name, m).enum} = {i}, /* 0x{m.frame_id:03X} */")
    out.append("    FCC_MSG_COUNT\n} fcc_msg_t;\n")
    out.append("/* CAN identifiers. */")
    for m in spec.messages:
        out.append(f"#define {_Names(db_name, m).enum}_ID 0x{m.frame_id:03X}u")
    out.append("")
    out.append("/* Value tables (VAL_). */")
    for m in spec.messages:
        for sig in m.message.signals:
            for value, choice in sorted((sig.choices or {}).items()):
                out.append(f"#define {_Names(db_name, m).enum}_{sig.name.upper()}_{choice} {value}u")
    out.append("")
    out.append("/* Physical values of each message (crc and counter are the frame layer's). */")
    for m in spec.messages:
        n = _Names(db_name, m)
        e2e = f", E2E data ID 0x{m.data_id:04X}" if m.protected else ""
        period = f"{m.cycle_ms} ms" if m.cycle_ms else "event"
        out.append(f"/* {m.name} (0x{m.frame_id:03X}, {period}, {', '.join(m.senders)} -> "
                   f"{', '.join(m.receivers)}{e2e}): {_c_comment(m.message.comment)} */")
        out.append("typedef struct {")
        for s in m.data_signals:
            doc = _field_doc(s, m.message.get_signal_by_name(s.name).comment)
            out.append(f"    {C_TYPES[_phys_type(s)]} {s.name}; /* {doc} */")
        out.append(f"}} {n.phys};\n")
    out.append("/* Any message, physical values. */\ntypedef union {")
    for m in spec.messages:
        n = _Names(db_name, m)
        out.append(f"    {n.phys} {n.snake};")
    out.append("} fcc_msg_data_t;\n")
    out.append("/* Any message, cantools raw struct (frame-layer scratch). */\ntypedef union {")
    for m in spec.messages:
        n = _Names(db_name, m)
        out.append(f"    {n.raw} {n.snake};")
    out.append("} fcc_bus_raw_t;\n")
    out.append("extern const fcc_bus_msg_desc_t fcc_bus_msg_table[FCC_MSG_COUNT];\n")
    out.extend(_app_header(spec))
    auths = [m for m in spec.messages if m.is_authenticator]
    width = max(len(m.secoc_pdus) for m in auths) if auths else 1
    out.append("/* SecOC: authenticator frames and the frames each authenticates (SecOC_DataID,")
    out.append(" * SecOC_Pdus); firmware/bus/fcc_secoc.h. */")
    out.append(f"#define FCC_SECOC_N_AUTH {len(auths)}u")
    out.append(f"#define FCC_SECOC_MAX_PDUS {width}u")
    out.append("typedef struct {\n    fcc_msg_t auth;       /* the authenticator frame */\n"
               "    uint16_t data_id;     /* SecOC data ID in the MAC input */\n"
               "    uint8_t n_pdus;       /* frames authenticated, concatenated in this order */\n"
               "    fcc_msg_t pdus[FCC_SECOC_MAX_PDUS];\n} fcc_secoc_desc_t;")
    out.append("extern const fcc_secoc_desc_t fcc_secoc_table[FCC_SECOC_N_AUTH];\n")
    out.append("#endif /* FCC_BUS_MSGS_H */")
    return "\n".join(out) + "\n"


def _signal_rows(m: dbc.MessageSpec, n: _Names) -> list[str]:
    rows = []
    for s in m.data_signals:
        rows.append(
            f'    {{"{s.name}", (uint16_t)offsetof({n.phys}, {s.name}), '
            f"(uint16_t)offsetof({n.raw}, {s.name}), FCC_FIELD_{_phys_type(s)}, "
            f"FCC_FIELD_{_raw_type(s)}, FCC_R({s.inv_scale}.0), "
            f"INT64_C({s.raw_min}), INT64_C({s.raw_max})}},")
    return rows


def generate_source(spec: dbc.BusSpec, db_name: str) -> str:
    out = [BANNER.format(name=SOURCE, dbc=f"dbc/{spec.path.name}"),
           "#include <stddef.h>\n", f'#include "{HEADER}"\n']
    for m in spec.messages:
        n = _Names(db_name, m)
        out.append(f"static const fcc_bus_signal_desc_t sig_{n.snake}[] = {{")
        out.extend(_signal_rows(m, n))
        out.append("};\n")
        out.append(f"static int unpack_{n.snake}(void *raw, const uint8_t data[8])\n{{\n"
                   f"    return {n.unpack}(raw, data, 8u);\n}}\n")
        out.append(f"static int pack_{n.snake}(uint8_t data[8], const void *raw)\n{{\n"
                   f"    return {n.pack}(data, raw, 8u);\n}}\n")
    out.append("const fcc_bus_msg_desc_t fcc_bus_msg_table[FCC_MSG_COUNT] = {")
    for m in spec.messages:
        n = _Names(db_name, m)
        out.append(
            f'    {{"{m.name}", 0x{m.frame_id:03X}u, 0x{m.data_id:04X}u, {m.max_delta_counter}u, '
            f"{m.cycle_ms}u, {_node_mask(spec.nodes, m.senders)}, "
            f"{_node_mask(spec.nodes, m.receivers)}, "
            f"(uint8_t)(sizeof sig_{n.snake} / sizeof sig_{n.snake}[0]), sig_{n.snake}, "
            f"unpack_{n.snake}, pack_{n.snake}}},")
    out.append("};\n")
    out.extend(_app_source(spec, db_name))
    out.append("const fcc_secoc_desc_t fcc_secoc_table[FCC_SECOC_N_AUTH] = {")
    for m in spec.messages:
        if m.is_authenticator:
            pdus = ", ".join(_Names(db_name, spec.by_name(p)).enum for p in m.secoc_pdus)
            out.append(f"    {{{_Names(db_name, m).enum}, 0x{m.secoc_data_id:04X}u, "
                       f"{len(m.secoc_pdus)}u, {{{pdus}}}}},")
    out.append("};")
    return "\n".join(out) + "\n"


def generate(dbc_path: Path, out_dir: Path) -> list[Path]:
    spec = dbc.load(dbc_path)
    _check_apps(spec)
    db_name = dbc_path.stem
    out_dir.mkdir(parents=True, exist_ok=True)
    files = {HEADER: generate_header(spec, db_name), SOURCE: generate_source(spec, db_name)}
    paths = []
    for name, text in files.items():
        path = out_dir / name
        path.write_text(text)
        paths.append(path)
    return paths


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="hil.bus.cgen", description=__doc__.splitlines()[0])
    parser.add_argument("dbc", type=Path)
    parser.add_argument("out_dir", type=Path)
    args = parser.parse_args(argv)
    try:
        for path in generate(args.dbc, args.out_dir):
            print(f"generated {path}")
    except (OSError, ValueError, KeyError) as exc:
        print(f"hil.bus.cgen: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
