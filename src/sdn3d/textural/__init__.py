"""The textural branch of 3D-SDN at inference: the generator G and encoder E (``renderer``) and the
per-instance texture codes (``codes``). Training lives in ``lightning_modules.textural``."""
