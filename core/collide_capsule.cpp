// placeholder: written with the narrowphase
