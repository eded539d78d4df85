# Config fragment for the small UML kernel with gpio-sim and vcan built in (sourced by
# build-gpio-kernel.sh; its bytes are part of the cache key). The recipe: start from tinyconfig;
# force 64-bit (tinyconfig leaves UML 32-bit, which cannot run the host's binaries); add just
# enough of a base system to run the host's dynamic binaries through hostfs; build CAN, vcan and
# the kernel's ISO-TP (CAN_ISOTP, so libldoem's can:isotp: transport and can-utils' isotpsend /
# isotprecv can be tested); gpio-sim with the v1 character-device uAPI that libgpiod 1.6 speaks;
# and PCI_MSI (via UML_PCI_OVER_VIRTIO) so that gpio-sim can map IRQs for edge events.
# shellcheck shell=sh
ldoem_gpio_kernel_options() {
  # $1: the scripts/config command line prefix
  cfg=$1
  # tinyconfig answers 64BIT=n on UML; a 32-bit UML cannot run the host's x86_64 binaries.
  $cfg -e 64BIT -e BINFMT_ELF -e BINFMT_SCRIPT -e MULTIUSER -e PRINTK -e BUG -e FUTEX -e EPOLL \
       -e SIGNALFD -e TIMERFD -e EVENTFD -e POSIX_TIMERS -e FILE_LOCKING -e SHMEM -e TMPFS \
       -e PROC_FS -e SYSFS -e DEVTMPFS -e DEVTMPFS_MOUNT -e HOSTFS -e MAGIC_SYSRQ \
       -e TTY -e UNIX98_PTYS -e STDERR_CONSOLE -e NULL_CHAN -e SSL \
       --set-str CON_CHAN null --set-str SSL_CHAN null
  # Networking: loopback TCP, AF_UNIX, SocketCAN raw + BCM + ISO-TP and vcan (vcan sits under NETDEVICES).
  $cfg -e NET -e UNIX -e INET -e NETDEVICES -e NET_CORE \
       -e CAN -e CAN_RAW -e CAN_BCM -e CAN_DEV -e CAN_VCAN -e CAN_ISOTP
  # NETDEVICES defaults ETHERNET on, which pulls PTP_1588_CLOCK that does not compile under
  # tinyconfig (no SRCU).
  $cfg -d ETHERNET -d WLAN -d PTP_1588_CLOCK -d PPS
  # gpio-sim and the v1 uAPI (GPIO_CDEV only has a prompt under EXPERT).
  $cfg -e CONFIGFS_FS -e GPIOLIB -e GPIO_CDEV -e GPIO_CDEV_V1 -e GPIO_SIM
  # Without PCI_MSI UML has NR_IRQS=64, all taken at boot: gpio-sim edge requests fail ENODEV.
  $cfg -e VIRTIO_UML -e UML_PCI_OVER_VIRTIO --set-val UML_PCI_OVER_VIRTIO_DEVICE_ID 1234
}
# Options that must read =y in the final .config (checked after olddefconfig).
LDOEM_GPIO_KERNEL_REQUIRED="64BIT HOSTFS DEVTMPFS UNIX98_PTYS CONFIGFS_FS CAN CAN_RAW CAN_BCM CAN_ISOTP CAN_VCAN GPIOLIB GPIO_CDEV GPIO_CDEV_V1 GPIO_SIM PCI_MSI SIGNALFD EPOLL TIMERFD INET UNIX"
