"""``python -m iecoop_examples.ch11_abstract_fb_vs_interface`` runs the chapter's ``main()``."""

from iecoop_examples.ch11_abstract_fb_vs_interface import main

if __name__ == "__main__":
    main()
