"""The stress suite: hard cases for both engines (python3 -m tests.stress.stress)."""
