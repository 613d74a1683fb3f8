"""Creational patterns: how function block instances come to exist on a PLC."""
