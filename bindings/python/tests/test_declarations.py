"""The binding mirrors include/crowdgaze.h exactly: every function declared with the
header's parameter and return types, every struct with its fields in order (and the C
compiler's sizes and offsets), every constant and enum value, and the numpy record dtypes
laid out as the structs."""

from __future__ import annotations

import ctypes
import os
import re
import subprocess
from ctypes import (
    POINTER,
    c_bool,
    c_char,
    c_char_p,
    c_double,
    c_float,
    c_int32,
    c_size_t,
    c_uint32,
    c_uint64,
)

import pytest
from conftest import REPOSITORY

import crowdgaze

# --- a small parser of the (cbindgen-generated, regular) header ---------------------------


def _defines(header: str) -> dict[str, str]:
    return dict(re.findall(r"(?m)^#define ((?:CG|cg)_\w+) (.+)$", header))


def _code(header: str) -> str:
    """The header without comments and preprocessor lines."""
    lines = []
    for line in header.splitlines():
        stripped = line.strip()
        if stripped.startswith("#"):
            continue
        lines.append(line.split("//")[0])
    text = "\n".join(lines)
    return re.sub(r"/\*.*?\*/", "", text, flags=re.S)


def parse_functions(header: str) -> dict[str, tuple[str, list[str]]]:
    """name -> (return type, [parameter types])."""
    functions = {}
    for match in re.finditer(r"(?m)^((?:const )?\w+ \*?)(cg_\w+)\(([^;]*?)\);", _code(header)):
        result, name, params = match.groups()
        types = []
        for param in " ".join(params.split()).split(","):
            param = param.strip()
            if param in ("void", ""):
                continue
            decl = re.match(r"^(.*?)(\w+)$", param)
            assert decl, param
            types.append(" ".join(decl.group(1).split()))
        functions[name] = (" ".join(result.split()), types)
    return functions


def parse_structs(header: str) -> dict[str, list[tuple[str, str, str | None]]]:
    """name -> [(field type, field name, array length or None)]."""
    structs = {}
    for name, body in re.findall(r"typedef struct (cg_\w+) \{(.*?)\} \1;", _code(header), re.S):
        fields = []
        for line in body.splitlines():
            line = line.strip()
            if not line:
                continue
            field = re.match(
                r"^((?:const )?(?:struct )?\w+ (?:\*const \*|\*)?)(\w+)(?:\[(\w+)\])?;$", line
            )
            assert field, line
            fields.append((" ".join(field.group(1).split()), field.group(2), field.group(3)))
        structs[name] = fields
    return structs


def parse_opaque(header: str) -> list[str]:
    return re.findall(r"(?m)^typedef struct (cg_\w+) \1;$", header)


def parse_enums(header: str) -> dict[str, dict[str, int]]:
    enums = {}
    for name, body in re.findall(r"enum (cg_\w+)[^{;]*\{(.*?)\};", _code(header), re.S):
        enums[name] = {
            member: int(value) for member, value in re.findall(r"(CG_\w+) = (\d+)", body)
        }
    return enums


BASE_TYPES = {
    "uint32_t": c_uint32,
    "uint64_t": c_uint64,
    "int32_t": c_int32,
    "size_t": c_size_t,
    "float": c_float,
    "double": c_double,
    "bool": c_bool,
    "cg_status": c_uint32,
    "char": c_char,
}


def expected_ctype(c_type: str):
    """The ctypes type a C type must be declared as (``const char *const *``, an array of
    strings, is a pointer to ``c_char_p``)."""
    stars = c_type.count("*")
    base = c_type.replace("*", "").replace("const ", "").replace("struct ", "").strip()
    if base == "void" and stars == 0:
        return None
    if base == "char" and stars >= 1:
        result: object = c_char_p
        stars -= 1
    else:
        result = BASE_TYPES.get(base) or crowdgaze.STRUCTS[base]
    for _ in range(stars):
        result = POINTER(result)
    return result


# --- the tests ------------------------------------------------------------------------------


def test_the_parser_sees_the_whole_header(header_text):
    functions = parse_functions(header_text)
    # Every `cg_...(` declaration line of the header is parsed.
    declared = set(re.findall(r"(?m)^[^/#\s].*?\b(cg_\w+)\(", header_text))
    assert declared == set(functions)
    assert len(functions) >= 50
    assert len(parse_structs(header_text)) >= 16
    assert parse_opaque(header_text) == ["cg_crowd", "cg_rig", "cg_view_blender"]


def test_every_header_function_is_declared_with_its_types(header_text):
    functions = parse_functions(header_text)
    assert set(crowdgaze.FUNCTIONS) == set(functions), "declared vs header"
    for name, (result, params) in functions.items():
        function = getattr(crowdgaze.lib, name)
        assert function.restype is expected_ctype(result), name
        assert function.argtypes is not None, name
        assert list(function.argtypes) == [expected_ctype(p) for p in params], name


def test_every_struct_mirrors_the_header_field_by_field(header_text):
    defines = _defines(header_text)
    structs = parse_structs(header_text)
    assert set(crowdgaze.STRUCTS) == set(structs) | set(parse_opaque(header_text))
    for name, fields in structs.items():
        ctype = crowdgaze.STRUCTS[name]
        mirrored = ctype._fields_
        assert [f[0] for f in mirrored] == [f[1] for f in fields], name
        for (field_name, field_type), (c_type, _, length) in zip(mirrored, fields):
            expected = expected_ctype(c_type)
            if length is not None:
                expected = expected * int(defines.get(length, length))
            assert field_type == expected or (
                length is not None
                and field_type._type_ is expected._type_
                and field_type._length_ == expected._length_
            ), f"{name}.{field_name}"
    for name in parse_opaque(header_text):
        assert ctypes.sizeof(crowdgaze.STRUCTS[name]) == 0, name  # opaque: pointers only


def test_sizes_and_offsets_agree_with_the_c_compiler(header_text, tmp_path):
    structs = parse_structs(header_text)
    lines = [
        "#include <stddef.h>",
        "#include <stdio.h>",
        '#include "crowdgaze.h"',
        "int main(void) {",
    ]
    for name, fields in structs.items():
        lines.append(f'    printf("{name} %zu\\n", sizeof({name}));')
        for _, field, _ in fields:
            lines.append(f'    printf("{name}.{field} %zu\\n", offsetof({name}, {field}));')
    lines += ["    return 0;", "}"]
    source = tmp_path / "layout.c"
    source.write_text("\n".join(lines))
    program = tmp_path / "layout"
    compiler = os.environ.get("CC", "cc")
    subprocess.run(
        [compiler, "-std=c99", "-I", str(REPOSITORY / "include"), str(source), "-o", str(program)],
        check=True,
    )
    output = subprocess.run([str(program)], check=True, capture_output=True, text=True).stdout
    layout = dict(line.rsplit(" ", 1) for line in output.splitlines())
    assert len(layout) == sum(1 + len(f) for f in structs.values())
    for key, value in layout.items():
        if "." in key:
            struct, field = key.split(".")
            assert getattr(crowdgaze.STRUCTS[struct], field).offset == int(value), key
        else:
            assert ctypes.sizeof(crowdgaze.STRUCTS[key]) == int(value), key


def test_struct_size_written_by_the_library_matches_ctypes():
    for init, ctype in [
        (crowdgaze.lib.cg_crowd_config_init, crowdgaze.CrowdConfig),
        (crowdgaze.lib.cg_character_desc_init, crowdgaze.CharacterDesc),
        (crowdgaze.lib.cg_object_desc_init, crowdgaze.ObjectDesc),
        (crowdgaze.lib.cg_entity_state_init, crowdgaze.EntityState),
        (crowdgaze.lib.cg_gaze_target_init, crowdgaze.GazeTarget),
        (crowdgaze.lib.cg_view_blender_config_init, crowdgaze.ViewBlenderConfig),
        (crowdgaze.lib.cg_rig_desc_init, crowdgaze.RigDesc),
    ]:
        value = ctype(struct_size=ctypes.sizeof(ctype))
        assert init(ctypes.byref(value)) == 0
        assert value.struct_size == ctypes.sizeof(ctype), ctype.__name__
    chain = crowdgaze.chain_desc_human()
    assert chain.struct_size == ctypes.sizeof(crowdgaze.ChainDesc)
    assert chain.joint_count == 10


def test_constants_and_enums_match(header_text):
    defines = _defines(header_text)
    assert len(defines) >= 11
    assert crowdgaze.cg_quat_IDENTITY == (0.0, 0.0, 0.0, 1.0)
    for name, value in defines.items():
        expected = 0xFFFFFFFF if value == "UINT32_MAX" else int(value, 0)
        assert getattr(crowdgaze, name) == expected, name
    enums = parse_enums(header_text)
    assert set(enums) == set(crowdgaze.ENUMS)
    for enum_name, members in enums.items():
        python_enum = crowdgaze.ENUMS[enum_name]
        prefix = enum_name.upper() + "_"
        assert {prefix + m.name: int(m) for m in python_enum} == members, enum_name
        for member, value in members.items():
            assert getattr(crowdgaze, member) == value


@pytest.mark.parametrize("ctype", list(crowdgaze.RECORD_DTYPES))
def test_record_dtypes_have_the_struct_layout(ctype):
    dtype = crowdgaze.RECORD_DTYPES[ctype]
    assert dtype.itemsize == ctypes.sizeof(ctype)
    assert list(dtype.names) == [name for name, _ in ctype._fields_]
    for name, field_type in ctype._fields_:
        assert dtype.fields[name][1] == getattr(ctype, name).offset, name
        assert dtype.fields[name][0].itemsize == ctypes.sizeof(field_type), name


def test_the_version_matches():
    assert crowdgaze.version_string() == crowdgaze.__version__
    assert crowdgaze.version() == (
        (crowdgaze.CG_VERSION_MAJOR << 16)
        | (crowdgaze.CG_VERSION_MINOR << 8)
        | crowdgaze.CG_VERSION_PATCH
    )
