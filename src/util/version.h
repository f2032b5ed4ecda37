/* version.h — esfera's version string. */
#ifndef ESF_VERSION_H
#define ESF_VERSION_H
#define ESF_VERSION "0.1.0"
#endif
