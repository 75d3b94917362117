"""Importing this module registers ``workcell/BoxTransfer-v0`` with Gymnasium, so that
``gymnasium.make("workcell.envs.registered:workcell/BoxTransfer-v0")`` works without a
prior :func:`workcell.envs.register` call. Nothing else imports it."""

from workcell.envs.registration import register

register()
