#!/usr/bin/env python3
"""Checks the Python client's constants against the wire contract.

usage: check_python.py [--self-test] CONTRACT_DUMP PYTHON_PACKAGE_DIR

CONTRACT_DUMP is the contract_dump program (it prints gport/contract/ as
JSON); PYTHON_PACKAGE_DIR holds the package gport (client/python). Checked:
  - every error code of the contract has its exception class in
    gport.errors, with that code, and gport.errors maps no other code;
  - gport._protocol.TOPICS are the contract's topics, in its order;
  - gport._protocol.CHANNEL_METHOD is one of the contract's methods;
  - gport._protocol.DEFAULT_SOCKET and SOCKET_ENV are the contract's.
Each difference is printed, naming the contract's entry and the Python name;
the exit status is 1 if there is any.

--self-test runs the check on deliberately drifted copies of the package's
values (a changed code, a missing class, an extra topic) and fails unless
each is caught, so the check cannot silently pass everything.
"""

from __future__ import annotations

import importlib
import json
import subprocess
import sys
from typing import Any

# The contract's name of each code, and the Python client's exception class
# for it (its public names, kept; docs/client-python.md).
PYTHON_CLASS = {
    "kParse": "ParseError",
    "kInvalidRequest": "InvalidRequest",
    "kUnknownMethod": "MethodNotFound",
    "kInvalidParams": "InvalidParams",
    "kInternal": "InternalError",
    "kLinkDown": "LinkDown",
    "kPermission": "PermissionDenied",
    "kNoAnswer": "NotAnswering",
    "kBusy": "Busy",
    "kNoSlot": "NoSlot",
    "kTooManyRequests": "TooManyRequests",
    "kConfigInvalid": "ConfigInvalid",
}


def python_values(package_dir: str) -> dict[str, Any]:
    """What the Python client says, as plain data."""
    sys.path.insert(0, package_dir)
    errors = importlib.import_module("gport.errors")
    protocol = importlib.import_module("gport._protocol")
    classes = {
        name: getattr(errors, name).code
        for name in dir(errors)
        if isinstance(getattr(errors, name), type)
        and issubclass(getattr(errors, name), errors.GportError)
    }
    return {
        "classes": classes,
        "by_code": {code: cls.__name__ for code, cls in errors._BY_CODE.items()},
        "topics": list(protocol.TOPICS),
        "channel_method": protocol.CHANNEL_METHOD,
        "default_socket": protocol.DEFAULT_SOCKET,
        "socket_env": protocol.SOCKET_ENV,
    }


def differences(contract: dict[str, Any], py: dict[str, Any]) -> list[str]:
    problems = []
    errors = contract["errors"]
    for name in errors:
        if name not in PYTHON_CLASS:
            problems.append(
                f"contract error {name} ({errors[name]}) has no Python class in "
                "check_python.py's PYTHON_CLASS: add one to gport/errors.py and the table"
            )
    for name, cls in PYTHON_CLASS.items():
        if name not in errors:
            problems.append(f"PYTHON_CLASS names {name}, which the contract does not have")
            continue
        code = errors[name]
        if cls not in py["classes"]:
            problems.append(f"contract error {name} ({code}): gport.errors has no class {cls}")
        elif py["classes"][cls] != code:
            problems.append(
                f"contract error {name} is {code}, gport.errors.{cls}.code is {py['classes'][cls]}"
            )
        if py["by_code"].get(code) != cls:
            problems.append(
                f"gport.errors._BY_CODE[{code}] is {py['by_code'].get(code)}, not {cls} ({name})"
            )
    extra = sorted(set(py["by_code"]) - set(errors.values()))
    for code in extra:
        problems.append(f"gport.errors maps {code} ({py['by_code'][code]}), not a contract code")
    if py["topics"] != contract["topics"]:
        problems.append(
            f"gport._protocol.TOPICS is {py['topics']}, the contract's topics are "
            f"{contract['topics']}"
        )
    if py["channel_method"] not in contract["methods"]:
        problems.append(
            f"gport._protocol.CHANNEL_METHOD {py['channel_method']!r} is not a contract method"
        )
    for key, name in (("default_socket", "DEFAULT_SOCKET"), ("socket_env", "SOCKET_ENV")):
        if py[key] != contract[key]:
            problems.append(
                f"gport._protocol.{name} is {py[key]!r}, the contract's is {contract[key]!r}"
            )
    return problems


def self_test(contract: dict[str, Any], py: dict[str, Any]) -> list[str]:
    """Drifts the Python values one way at a time; each must be reported."""
    failures = []
    if differences(contract, py):
        failures.append("the real package already differs; fix that first")

    def drifted(change: str, mutate: Any, expect: str) -> None:
        copy = json.loads(json.dumps(py))
        copy["by_code"] = {int(k): v for k, v in copy["by_code"].items()}
        mutate(copy)
        found = differences(contract, copy)
        if not any(expect in p for p in found):
            failures.append(f"{change}: not caught (got {found})")

    drifted("Busy.code changed", lambda p: p["classes"].update(Busy=-32099), "Busy.code is -32099")
    drifted("NoSlot removed", lambda p: p["classes"].pop("NoSlot"), "no class NoSlot")
    drifted("extra code", lambda p: p["by_code"].update({-32050: "Busy"}), "maps -32050")
    drifted("topic added", lambda p: p["topics"].append("video"), "TOPICS is")
    drifted("topic dropped", lambda p: p["topics"].remove("capture"), "TOPICS is")
    drifted("socket moved", lambda p: p.update(default_socket="/tmp/g.sock"), "DEFAULT_SOCKET is")
    drifted("env renamed", lambda p: p.update(socket_env="GPORTD_SOCKET"), "SOCKET_ENV is")
    drifted("method renamed", lambda p: p.update(channel_method="channel"), "CHANNEL_METHOD")
    return failures


def main(argv: list[str]) -> int:
    test = argv[:1] == ["--self-test"]
    args = argv[1:] if test else argv
    if len(args) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    dump, package_dir = args
    contract = json.loads(subprocess.run([dump], check=True, capture_output=True).stdout)
    py = python_values(package_dir)
    problems = self_test(contract, py) if test else differences(contract, py)
    for problem in problems:
        print(f"check_python: {problem}", file=sys.stderr)
    if problems:
        return 1
    what = "every drift was caught" if test else "the Python client agrees with the contract"
    print(f"check_python: {what} ({len(contract['errors'])} error codes, "
          f"{len(contract['topics'])} topics)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
