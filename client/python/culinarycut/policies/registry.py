"""Policies by name: the built-in ones, those other packages register under the entry-point group
"culinarycut.policies", and any class given as "module:Class"."""
from __future__ import annotations

import importlib
from importlib.metadata import entry_points

from culinarycut.policies.aggressive_oracle import AggressiveOraclePolicy
from culinarycut.policies.base import Policy
from culinarycut.policies.floor_policies import NoOpPolicy, RandomPolicy
from culinarycut.policies.grpc_policy import GrpcPolicy
from culinarycut.policies.oracle_policy import OraclePolicy

BUILT_IN = {cls.name: cls for cls in (OraclePolicy, AggressiveOraclePolicy, RandomPolicy, NoOpPolicy, GrpcPolicy)}


class UnknownPolicy(ValueError):
    pass


def policy_names() -> list[str]:
    return sorted(set(BUILT_IN) | {ep.name for ep in entry_points(group="culinarycut.policies")})


def policy_class(name: str) -> type[Policy]:
    if name in BUILT_IN:
        return BUILT_IN[name]
    for ep in entry_points(group="culinarycut.policies"):
        if ep.name == name:
            return ep.load()
    if ":" in name:
        module, _, attribute = name.partition(":")
        try:
            return getattr(importlib.import_module(module), attribute)
        except (ImportError, AttributeError) as err:
            raise UnknownPolicy(f"policy {name!r} could not be loaded: {err}") from None
    raise UnknownPolicy(f"unknown policy {name!r}; choose one of: {', '.join(policy_names())} "
                        "(or give module:Class)")


def make_policy(name: str, options: dict | None = None) -> Policy:
    cls = policy_class(name)
    try:
        return cls(**(options or {}))
    except TypeError as err:
        raise ValueError(f"policy {name!r}: bad options {sorted(options or {})}: {err}") from None
