"""The course's examples, one runnable module per chapter (``python -m iecoop_examples.ch01_classes_and_objects``)."""
